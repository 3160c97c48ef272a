# Speed and accuracy of the exact simulator against solve_ivp (DOP853) with terminal events.


rule bench:
    input:
        "results/bench/simulator.nc",


rule bench_simulator:
    output:
        nc="results/bench/simulator.nc",
        md="results/tables/bench_simulator.md",
    params:
        **config["bench"],
    conda:
        "../envs/vibroimpact.yaml"
    log:
        "logs/bench/simulator.log",
    benchmark:
        "benchmarks/bench/simulator.tsv"
    threads: 1
    script:
        "../scripts/bench_simulator.py"
