# Every branch the rules above name, one job per incline: a branch takes under a second to continue and about
# as long again to start a job (imports, the compiled kernels loaded), so one job for an incline's branches saves
# that start-up for each, and a job that reads one incline's branches waits for those only.  Each dataset is the
# one a job of its own (rule branch: any other incline, word or restitution, e.g. a study's) writes, by the same
# script; the simulated attractors along a branch are named by figures only.  Included last: it takes the
# branches every rule included before it names (common.smk, NAMED_BRANCHES).
R_KEY = fmt(config["physics"]["r"])
# the configured sweeps' branches (sweep_branches names them only when the jobs are planned)
for _sc in SWEEPS.values():
    for _w in ("BT", "BBT"):
        if _w in WORDS:
            branch_path("orbit", _sc["beta"], _w, _sc["vary"])
# (a word the config does not define names a branch no job can make: a rule outside the target asked for)
BATCH = [key for key in NAMED_BRANCHES if key[1] in WORDS]

for _beta in dict.fromkeys(b for b, _, _ in BATCH):
    _keys = [key for key in BATCH if key[0] == _beta]

    rule:
        name:
            batch_rule(_beta)
        output:
            orbits=[branch_path("orbit", float(b), w, v) for b, w, v in _keys],
            energies=[energy_path("branch", float(b), w, v) for b, w, v in _keys],
            sims=[
                branch_path("sim", float(b), w, v)
                for b, w, v in _keys
                if NAMED_BRANCHES[(b, w, v)]
            ],
        log:
            f"logs/branches/beta-{_beta}_r-{R_KEY}/batch.log",
        benchmark:
            f"benchmarks/branches/beta-{_beta}_r-{R_KEY}/batch.tsv"
        priority: 10  # a long chain: started early, so that short jobs fill the other core to the end
        conda:
            "../envs/vibroimpact.yaml"
        params:
            jobs=[branch_job(b, R_KEY, w, v) for b, w, v in _keys],
            # the simulated attractors along a branch (the figures' open circles): how many, their tolerance
            simulated=dict(
                n=config["branches"]["simulated_points"],
                tol=config["attractor"]["tol"],
            ),
            code=code("branch.py"),
        script:
            "../scripts/branch.py"

    workflow.ruleorder(batch_rule(_beta), "branch")
