# Knocks (vibroimpact.analysis.robust): on the plane of a design map, every point run from the design maps' start
# states to its attractors, the critical shock of each attractor, the design that keeps its output under the
# configured knock, and the basins a knock crosses in a (Z, Zdot) section of one design.
KNOCKS = config["knocks"]


rule knock_map:
    output:
        "results/knocks/map.nc",
    log:
        "logs/knocks/map.log",
    benchmark:
        "benchmarks/knock_map/map.tsv"
    priority: 10  # a long chain: started early, so that short jobs fill the other core to the end
    conda:
        "../envs/vibroimpact.yaml"
    # parallel inside, but seconds long at the draft preset: two such jobs side by side use 2 cores better than
    # one on both (--set-threads gives it more; the SLURM profile does)
    threads: 1
    params:
        spec=config["maps"][KNOCKS["map"]],
        knocks=KNOCKS,
        device=DEVICE_SPEC,
        design=DESIGN,
        preset=RESOLUTION["knocks"],
        max_periods=config["sweeps"]["max_periods"],
        tol=config["sweeps"]["tol"],
        window=config["sweeps"]["window"],
        window_time=config["energy"]["window_time"],
        code=code("knock_map.py"),
    script:
        "../scripts/knock_map.py"


rule knock_section:
    output:
        "results/knocks/section.nc",
    log:
        "logs/knocks/section.log",
    benchmark:
        "benchmarks/knock_section/section.tsv"
    priority: 10  # a long chain: started early, so that short jobs fill the other core to the end
    conda:
        "../envs/vibroimpact.yaml"
    # parallel inside, but seconds long at the draft preset: two such jobs side by side use 2 cores better than
    # one on both (--set-threads gives it more; the SLURM profile does)
    threads: 1
    params:
        knocks=KNOCKS,
        device=DEVICE_SPEC,
        design=DESIGN,
        preset=RESOLUTION["knocks"],
        max_periods=config["sweeps"]["max_periods"],
        tol=config["sweeps"]["tol"],
        window=config["sweeps"]["window"],
        window_time=config["energy"]["window_time"],
        code=code("knock_section.py"),
    script:
        "../scripts/knock_section.py"


rule knocks_table:
    input:
        "results/knocks/map.nc",
        # the knock map's job time (its benchmark file), for the cost line
        cost="benchmarks/knock_map/map.tsv",
    output:
        csv="results/tables/knocks.csv",
        md="results/tables/knocks.md",
    log:
        "logs/tables/knocks.log",
    priority: 10  # a long chain: started early, so that short jobs fill the other core to the end
    conda:
        "../envs/vibroimpact.yaml"
    params:
        table_betas=DESIGN["table_betas"],
        code=code("knocks_table.py"),
    script:
        "../scripts/knocks_table.py"
