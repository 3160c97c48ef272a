# Speed and accuracy of the exact simulator against solve_ivp (DOP853) with terminal events.


rule bench:
    input:
        "results/bench/simulator.nc",
        "results/figures/work_precision.png",
        "results/figures/failure_map.png",
        "results/figures/lyapunov_precision.png",


rule bench_simulator:
    output:
        nc="results/bench/simulator.nc",
        kernel="results/bench/kernel.nc",
        md="results/tables/bench_simulator.md",
    log:
        "logs/bench/simulator.log",
    benchmark:
        "benchmarks/bench/simulator.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    threads: workflow.cores  # timed: run alone
    params:
        **config["bench"],
        n_impacts=RESOLUTION["bench_size"]["n_impacts"],
        n_impacts_ivp=RESOLUTION["bench_size"]["n_impacts_ivp"],
        code=code("bench_simulator.py"),
    script:
        "../scripts/bench_simulator.py"


rule work_precision:
    output:
        nc="results/bench/work_precision.nc",
        md="results/tables/work_precision.md",
        matched="results/bench/matched_accuracy.nc",
        matched_md="results/tables/matched_accuracy.md",
    log:
        "logs/bench/work_precision.log",
    benchmark:
        "benchmarks/bench/work_precision.tsv"
    priority: 10  # a long chain: started early, so that short jobs fill the other core to the end
    conda:
        "../envs/vibroimpact.yaml"
    threads: workflow.cores  # timed: run alone
    params:
        **config["work_precision"],
        n_err=RESOLUTION["bench_size"]["n_err"],
        code=code("work_precision.py"),
    script:
        "../scripts/work_precision.py"


rule lyapunov_precision:
    """Largest Lyapunov exponent by the tangent map, Benettin and time-series estimators: error against cost."""
    output:
        nc="results/bench/lyapunov_precision.nc",
        md="results/tables/lyapunov_precision.md",
    log:
        "logs/bench/lyapunov_precision.log",
    benchmark:
        "benchmarks/bench/lyapunov_precision.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    threads: workflow.cores  # timed: run alone
    params:
        **config["lyapunov_precision"],
        **RESOLUTION["bench_size"]["lyapunov"],
        code=code("lyapunov_precision.py"),
    script:
        "../scripts/lyapunov_precision.py"


rule failure_map:
    output:
        nc="results/bench/failure_map.nc",
        md="results/tables/failure_map.md",
    log:
        "logs/bench/failure_map.log",
    benchmark:
        "benchmarks/bench/failure_map.tsv"
    # the first job: its solve_ivp runs come first and need no compiled kernel, so the job beside it compiles the
    # event loop alone (two jobs that start together both compile it)
    priority: 20
    conda:
        "../envs/vibroimpact.yaml"
    threads: 1  # outcomes, not timings: runs beside other jobs (max_seconds only bounds a stalled method)
    params:
        **config["failure_map"],
        max_seconds=RESOLUTION["bench_size"]["max_seconds"],
        code=code("failure_map.py"),
    script:
        "../scripts/failure_map.py"


rule analytics_accuracy:
    input:
        # the "exact" G1 and G2 it measures against: the analytic branches' grazing point and fold
        branch21=branch_path("orbit", SWEEPS["figBiS"]["beta"], "BBT"),
        branch31=branch_path("orbit", SWEEPS["figBiS"]["beta"], "BBBT"),
    output:
        nc="results/bench/analytics_accuracy.nc",
    log:
        "logs/bench/analytics_accuracy.log",
    benchmark:
        "benchmarks/bench/analytics_accuracy.tsv"
    priority: 10  # a long chain: started early, so that short jobs fill the other core to the end
    conda:
        "../envs/vibroimpact.yaml"
    threads: workflow.cores  # timed: run alone
    params:
        code=code("analytics_accuracy.py"),
    script:
        "../scripts/analytics_accuracy.py"


rule workflow_cost:
    input:
        # everything else of the default target first, so that its benchmark files exist
        "results/checks/paper_values.csv",
        # every figure of the registry the default target draws
        figure_targets("all", formats=["png"]),
        "results/tables/design.md",
        "results/tables/transitions.md",
    output:
        csv="results/tables/workflow_cost.csv",
        md="results/tables/workflow_cost.md",
    log:
        "logs/tables/workflow_cost.log",
    conda:
        "../envs/vibroimpact.yaml"
    params:
        bench_dir="benchmarks",
        code=code("workflow_cost.py"),
    script:
        "../scripts/workflow_cost.py"


rule bench_figure:
    """Draw a speed-and-accuracy figure from its saved dataset (redrawn without rerunning the timings)."""
    input:
        "results/bench/{bench}.nc",
    output:
        **figure_formats("results/figures/{bench}"),
        png=report(
            "results/figures/{bench}.png",
            caption=figure_caption("bench_figure"),
            category=figure_category("bench_figure"),
        ),
        data="results/figures/data/{bench}.nc",
    log:
        "logs/figures/{bench}.log",
    benchmark:
        "benchmarks/bench_figure/{bench}.tsv"
    wildcard_constraints:
        bench="work_precision|failure_map|analytics_accuracy|lyapunov_precision",
    priority: 10  # a long chain: started early, so that short jobs fill the other core to the end
    conda:
        "../envs/vibroimpact.yaml"
    params:
        code=code("bench_figure.py"),
    script:
        "../scripts/bench_figure.py"


rule speed_summary:
    """The speed-and-accuracy page's numbers, one row each with its source (the page cites the rows)."""
    input:
        kernel="results/bench/kernel.nc",
        simulator="results/bench/simulator.nc",
        work_precision="results/bench/work_precision.nc",
        matched_accuracy="results/bench/matched_accuracy.nc",
        failure_map="results/bench/failure_map.nc",
        analytics_accuracy="results/bench/analytics_accuracy.nc",
        lyapunov_precision="results/bench/lyapunov_precision.nc",
        workflow_cost="results/tables/workflow_cost.csv",
    output:
        md="results/tables/speed_summary.md",
    log:
        "logs/tables/speed_summary.log",
    conda:
        "../envs/vibroimpact.yaml"
    params:
        code=code("speed_summary.py"),
    script:
        "../scripts/speed_summary.py"
