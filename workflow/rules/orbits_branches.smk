# Analytic branches of periodic orbits with stability and located critical/grazing points.


rule branch:
    output:
        orbits="results/branches/beta-{beta}_r-{r}/orbit-{word}_vary-{vary}.nc",
        # its output voltages and averages (vibroimpact.analysis.energy), in the same job: a second job would
        # cost more in start-up than the computation
        energies="results/energy/beta-{beta}_r-{r}/orbit-{word}_vary-{vary}.nc",
    log:
        "logs/branches/beta-{beta}_r-{r}/orbit-{word}_vary-{vary}.log",
    benchmark:
        "benchmarks/branches/beta-{beta}_r-{r}/orbit-{word}_vary-{vary}.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        jobs=lambda wc: [branch_job(wc.beta, wc.r, wc.word, wc.vary)],
        code=code("branch.py"),
    script:
        "../scripts/branch.py"


rule table1:
    input:
        lambda wc: scene_branch_files("fig3"),
    output:
        csv="results/tables/table1.csv",
        md="results/tables/table1.md",
    log:
        "logs/tables/table1.log",
    benchmark:
        "benchmarks/table1/table1.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        code=code("table1.py"),
    script:
        "../scripts/table1.py"


# The paper's d_graz ("the maximum value for 2:1 period-2 solutions") along each sweep of the check, every
# incline by length and by force: the 2:1 fold, where the sweeps meet the 2:1, the 1:1 exit and the band between.
rule d_graz_table:
    input:
        sweeps=[sweep_path(p) for p in D_GRAZ_SWEEPS],
        transitions=[sweep_path(p, "-transitions") for p in D_GRAZ_SWEEPS],
        # the 2:1 branch along each sweep's line (same incline, same parameter varied)
        branches=[
            branch_path("orbit", SWEEPS[p]["beta"], "BBT", SWEEPS[p]["vary"])
            for p in D_GRAZ_SWEEPS
        ],
    output:
        csv="results/tables/d_graz.csv",
        md="results/tables/d_graz.md",
    log:
        "logs/tables/d_graz.log",
    benchmark:
        "benchmarks/d_graz_table/d_graz.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        names=D_GRAZ_SWEEPS,
        code=code("d_graz_table.py"),
    script:
        "../scripts/d_graz_table.py"
