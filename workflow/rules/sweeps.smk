# Numerical sweeps, located transitions and bistability, basins and regime maps.


rule sweep:
    input:
        # the continued 1:1 and 2:1 branches on the sweep's parameters: a period lost within critical
        # slowing of a branch's flip is a period doubling there (vibroimpact.period_doublings)
        branches=sweep_branches,
    output:
        sweep="results/sweeps/beta-{beta}_r-{r}/{sweep}.nc",
        # its located transitions and bistable intervals, and its output voltages and averages
        # (vibroimpact.analysis.energy), in the same job: separate jobs would cost more in start-up
        transitions="results/sweeps/beta-{beta}_r-{r}/{sweep}-transitions.nc",
        energy="results/energy/beta-{beta}_r-{r}/{sweep}.nc",
    log:
        "logs/sweeps/beta-{beta}_r-{r}/{sweep}.log",
    benchmark:
        "benchmarks/sweeps/beta-{beta}_r-{r}/{sweep}.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        scene=sweep_scene,
        device=DEVICE_SPEC,
        r=lambda wc: r_value(wc.r),
        sweeps={k: v for k, v in config["sweeps"].items() if k != "scenes"},
        points=RESOLUTION["sweep_points"],
        window_time=config["energy"]["window_time"],
        locate=config["sweeps"]["locate"],
        code=code("sweep.py"),
    script:
        "../scripts/sweep.py"


rule basins:
    output:
        "results/basins/beta-{beta}_r-{r}/{basin}.nc",
    log:
        "logs/basins/beta-{beta}_r-{r}/{basin}.log",
    benchmark:
        "benchmarks/basins/beta-{beta}_r-{r}/{basin}.tsv"
    priority: 10  # a long chain: started early, so that short jobs fill the other core to the end
    conda:
        "../envs/vibroimpact.yaml"
    # parallel inside, but seconds long at the draft preset: two such jobs side by side use 2 cores better than
    # one on both (--set-threads gives it more; the SLURM profile does)
    threads: 1
    params:
        spec=lambda wc: config["basins"][wc.basin],
        device=DEVICE_SPEC,
        grid=RESOLUTION["basin_grid"],
        tol=config["sweeps"]["tol"],
        code=code("basins.py"),
    script:
        "../scripts/basins.py"


rule regime_map:
    output:
        "results/maps/{map}_r-{r}.nc",
    log:
        "logs/maps/{map}_r-{r}.log",
    benchmark:
        "benchmarks/maps/{map}_r-{r}.tsv"
    priority: 10  # a long chain: started early, so that short jobs fill the other core to the end
    conda:
        "../envs/vibroimpact.yaml"
    # parallel inside, but seconds long at the draft preset: two such jobs side by side use 2 cores better than
    # one on both (--set-threads gives it more; the SLURM profile does)
    threads: 1
    params:
        # a non-dimensional plane's fixed parameter at the bifurcation set's incline
        spec=lambda wc: (
            ALL_MAPS[wc.map]
            if wc.map in config["maps"]
            else {"beta": config["bifurcation"]["beta"]} | ALL_MAPS[wc.map]
        ),
        device=DEVICE_SPEC,
        grid=RESOLUTION["map_grid"],
        max_periods=config["sweeps"]["max_periods"],
        tol=config["sweeps"]["tol"],
        code=code("regime_map.py"),
    script:
        "../scripts/regime_map.py"


rule bistability_portraits:
    input:
        branch21=branch_path("orbit", SWEEPS["figBiS"]["beta"], "BBT"),
        branch31=branch_path("orbit", SWEEPS["figBiS"]["beta"], "BBBT"),
        transitions=sweep_path("figBiS", "-transitions"),
        sweep=sweep_path("figBiS"),
    output:
        sweep_path("figBiS", "-portraits"),
    log:
        "logs/sweeps/figBiS-portraits.log",
    benchmark:
        "benchmarks/bistability_portraits/portraits.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        samples_per_unit=RESOLUTION["samples_per_unit"],
        d_mid=config["basins"]["figBiS"]["d"],  # Fig BiS (e), (f): both motions at the configured bistable point
        code=code("bistability_portraits.py"),
    script:
        "../scripts/bistability_portraits.py"


rule figBiS:
    input:
        sweep=sweep_path("figBiS"),
        transitions=sweep_path("figBiS", "-transitions"),
        portraits=sweep_path("figBiS", "-portraits"),
        branch21=branch_path("orbit", SWEEPS["figBiS"]["beta"], "BBT"),
        branch31=branch_path("orbit", SWEEPS["figBiS"]["beta"], "BBBT"),
    output:
        **figure_formats("results/figures/figBiS"),
        png=report(
            "results/figures/figBiS.png",
            caption=figure_caption("figBiS"),
            category=figure_category("figBiS"),
        ),
        data="results/figures/data/figBiS.nc",
    log:
        "logs/figures/figBiS.log",
    benchmark:
        "benchmarks/figBiS/figBiS.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        code=code("fig_bis.py"),
    script:
        "../scripts/fig_bis.py"


rule fig_basins:
    input:
        basin_path("figBiS"),
    output:
        **figure_formats("results/figures/basins"),
        png=report(
            "results/figures/basins.png",
            caption=figure_caption("fig_basins"),
            category=figure_category("fig_basins"),
        ),
        data="results/figures/data/basins.nc",
    log:
        "logs/figures/basins.log",
    benchmark:
        "benchmarks/fig_basins/basins.tsv"
    priority: 10  # a long chain: started early, so that short jobs fill the other core to the end
    conda:
        "../envs/vibroimpact.yaml"
    params:
        code=code("fig_basins.py"),
    script:
        "../scripts/fig_basins.py"


rule fig_regime_map:
    input:
        [map_path(m) for m in config["maps"]],
    output:
        **figure_formats("results/figures/regime_map"),
        png=report(
            "results/figures/regime_map.png",
            caption=figure_caption("fig_regime_map"),
            category=figure_category("fig_regime_map"),
        ),
        data="results/figures/data/regime_map.nc",
    log:
        "logs/figures/regime_map.log",
    benchmark:
        "benchmarks/fig_regime_map/regime_map.tsv"
    priority: 10  # a long chain: started early, so that short jobs fill the other core to the end
    conda:
        "../envs/vibroimpact.yaml"
    params:
        scans=SWEEPS,  # the paper's sweeps, drawn over the maps whose plane they lie in
        code=code("fig_regime_map.py"),
    script:
        "../scripts/fig_regime_map.py"


rule transitions_table:
    input:
        [sweep_path(n, "-transitions") for n in SWEEPS],
    output:
        "results/tables/transitions.md",
    log:
        "logs/tables/transitions.log",
    benchmark:
        "benchmarks/transitions_table/transitions.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        names=list(SWEEPS),
        code=code("transitions_table.py"),
    script:
        "../scripts/transitions_table.py"


# Is the "apparently chaotic" motion chaos? lambda_1 of every sweep point under its velocity bifurcation
# diagram, with B, d_graz (the 2:1 fold) and G1 of the continued branches and the 1:1 exit of each sweep; and the
# chaotic windows of d with their exponents and what a chaotic device delivers (window and long-run averages).
rule lyapunov_figure:
    input:
        sweeps=[sweep_path(p) for p in config["chaos"]["panels"]],
        # the 1:1 exit of each sweep
        transitions=[sweep_path(p, "-transitions") for p in config["chaos"]["panels"]],
        # the table of chaotic windows and outputs covers every sweep (figure or not)
        table_sweeps=[sweep_path(p) for p in SWEEPS],
        table_transitions=[sweep_path(p, "-transitions") for p in SWEEPS],
        table_energies=[energy_path("sweep", SWEEPS[p]["beta"], p) for p in SWEEPS],
        orbits=[
            branch_path("orbit", SWEEPS[p]["beta"], w, SWEEPS[p]["vary"])
            for p in config["chaos"]["panels"]
            for w in ("BT", "BBT")
            if w in WORDS
        ],
    output:
        **figure_formats("results/figures/lyapunov"),
        png=report(
            "results/figures/lyapunov.png",
            caption=figure_caption("lyapunov_figure"),
            category=figure_category("lyapunov_figure"),
        ),
        data="results/figures/data/lyapunov.nc",
        md="results/tables/chaos.md",
        windows="results/tables/chaos_windows.csv",
        outputs="results/tables/chaos_outputs.csv",
    log:
        "logs/figures/lyapunov.log",
    benchmark:
        "benchmarks/lyapunov_figure/lyapunov.tsv"
    priority: 10  # the longest figure: drawn as soon as its data are, so that short jobs fill the other core to the end
    conda:
        "../envs/vibroimpact.yaml"
    params:
        panels=config["chaos"]["panels"],
        table_sweeps=list(SWEEPS),
        words=[w for w in ("BT", "BBT") if w in WORDS],
        code=code("lyapunov_figure.py"),
    script:
        "../scripts/lyapunov_figure.py"
