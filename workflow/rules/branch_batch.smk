# Every branch the rules above name, in one job: a branch takes under a second to continue and about as long
# again to start a job (imports, the compiled kernels loaded), so one job for all of them saves that start-up
# for each.  Each dataset is the one its own job (rule branch: any other incline, word or restitution, e.g. a
# study's) writes, by the same script; the simulated attractors along a branch are named by figures only.  Included last: it takes the branches every rule
# included before it names (common.smk, NAMED_BRANCHES).
R_KEY = fmt(config["physics"]["r"])
# the configured sweeps' branches (sweep_branches names them only when the jobs are planned)
for _sc in SWEEPS.values():
    for _w in ("BT", "BBT"):
        if _w in WORDS:
            branch_path("orbit", _sc["beta"], _w, _sc["vary"])
# (a word the config does not define names a branch no job can make: a rule outside the target asked for)
BATCH = [key for key in NAMED_BRANCHES if key[1] in WORDS]
BATCH_SIMS = [key for key in BATCH if NAMED_BRANCHES[key]]
BATCH_STEMS = [f"beta-{b}_r-{R_KEY}/orbit-{w}_vary-{v}.nc" for b, w, v in BATCH]

if BATCH:

    rule branches:
        output:
            orbits=[f"results/branches/{stem}" for stem in BATCH_STEMS],
            energies=[f"results/energy/{stem}" for stem in BATCH_STEMS],
            sims=[
                f"results/branches/beta-{b}_r-{R_KEY}/sim-{w}_vary-{v}.nc"
                for b, w, v in BATCH_SIMS
            ],
        log:
            "logs/branches/batch.log",
        benchmark:
            "benchmarks/branches/batch.tsv"
        priority: 10  # a long chain: started early, so that short jobs fill the other core to the end
        conda:
            "../envs/vibroimpact.yaml"
        params:
            jobs=[branch_job(b, R_KEY, w, v) for b, w, v in BATCH],
            # the simulated attractors along a branch (the figures' open circles): how many, their tolerance
            simulated=dict(
                n=config["branches"]["simulated_points"],
                tol=config["attractor"]["tol"],
            ),
            code=code("branch.py"),
        script:
            "../scripts/branch.py"

    ruleorder: branches > branch
