# Analytic branches of periodic orbits with stability and located critical/grazing points.


rule branch:
    output:
        orbit="results/branches/beta-{beta}_r-{r}/orbit-{word}_vary-{vary}.nc",
        # its output voltages and averages (vibroimpact.analysis.energy), in the same job: a second job would
        # cost more in start-up than the computation
        energy="results/energy/beta-{beta}_r-{r}/orbit-{word}_vary-{vary}.nc",
    log:
        "logs/branches/beta-{beta}_r-{r}/orbit-{word}_vary-{vary}.log",
    benchmark:
        "benchmarks/branches/beta-{beta}_r-{r}/orbit-{word}_vary-{vary}.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        beta=lambda wc: beta_value(wc.beta),
        device=DEVICE_SPEC,
        r=lambda wc: r_value(wc.r),
        word=lambda wc: wc.word,
        vary=lambda wc: wc.vary,
        spec=lambda wc: WORDS[wc.word],
        # branches.d_range and .force, widened to the d every figure draws these branches over
        d_range=lambda wc: CFG.branch_d_range(beta_value(wc.beta), r_value(wc.r)),
        force=lambda wc: CFG.branch_force(beta_value(wc.beta)),
        step=RESOLUTION["branch_step"],
        code=code("branch.py"),
    script:
        "../scripts/branch.py"


rule branch_simulated:
    input:
        "results/branches/beta-{beta}_r-{r}/orbit-{word}_vary-{vary}.nc",
    output:
        "results/branches/beta-{beta}_r-{r}/sim-{word}_vary-{vary}.nc",
    log:
        "logs/branches/beta-{beta}_r-{r}/sim-{word}_vary-{vary}.log",
    benchmark:
        "benchmarks/branches/beta-{beta}_r-{r}/sim-{word}_vary-{vary}.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        n=config["branches"]["simulated_points"],
        tol=config["attractor"]["tol"],
        code=code("branch_simulated.py"),
    script:
        "../scripts/branch_simulated.py"


rule table1:
    input:
        lambda wc: scene_branch_files("fig3"),
        # d_graz beside the 2:1 fold: the length sweep's located transitions at each incline with one
        transitions=lambda wc: [
            sweep_path(p, "-transitions")
            for p in length_sweeps(BRANCH_SCENES["fig3"]["betas"]).values()
        ],
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
        betas=BRANCH_SCENES["fig3"]["betas"],
        code=code("table1.py"),
    script:
        "../scripts/table1.py"
