# Design under multistability (vibroimpact.analysis.design): on the planes of regime maps, the attractors reached
# from the same start states at every point, their shares and outputs (in chunks of grid rows, separate
# jobs), the tolerance margin to the bifurcation curves of the same plane, the maps and the table of the
# best robust designs.
wildcard_constraints:
    dmap="|".join(DESIGN["maps"]),
    chunk=r"\d+",


rule design_maps:
    input:
        figure_targets("design_maps"),
        "results/tables/design_robust.md",


rule design_chunk:
    output:
        "results/design/{dmap}/chunk-{chunk}.nc",
    log:
        "logs/design/{dmap}-chunk-{chunk}.log",
    benchmark:
        "benchmarks/design_chunk/{dmap}-{chunk}.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    # parallel inside, but with 2 threads a chunk kept ~1.1 cores busy: two chunks side by side use 2 cores better
    # (--set-threads gives more; the SLURM profile gives 2)
    threads: 1
    params:
        spec=lambda wc: config["maps"][wc.dmap],
        device=DEVICE_SPEC,
        design=DESIGN,
        preset=RESOLUTION["design"],
        max_periods=config["sweeps"]["max_periods"],
        tol=config["sweeps"]["tol"],
        window=config["sweeps"]["window"],
        window_time=config["energy"]["window_time"],
        code=code("design_chunk.py"),
    script:
        "../scripts/design_chunk.py"


rule design_map:
    input:
        chunks=lambda wc: design_chunks(wc.dmap),
        curves="results/bifurcation/{dmap}.nc",
    output:
        "results/design/{dmap}.nc",
    log:
        "logs/design/{dmap}.log",
    benchmark:
        "benchmarks/design_map/{dmap}.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        tolerance=DESIGN["tolerance"],
        code=code("design_map.py"),
    script:
        "../scripts/design_map.py"


rule fig_design_map:
    input:
        design="results/design/{dmap}.nc",
        curves="results/bifurcation/{dmap}.nc",
    output:
        **figure_formats("results/figures/design_map_{dmap}"),
        png=report(
            "results/figures/design_map_{dmap}.png",
            caption=figure_caption("fig_design_map"),
            category=figure_category("fig_design_map"),
        ),
        data="results/figures/data/design_map_{dmap}.nc",
    log:
        "logs/figures/design_map_{dmap}.log",
    benchmark:
        "benchmarks/fig_design_map/{dmap}.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        budget=DESIGN["budget"],
        table_betas=DESIGN["table_betas"],
        code=code("fig_design_map.py"),
    script:
        "../scripts/fig_design_map.py"


rule design_robust:
    input:
        maps=expand("results/design/{dmap}.nc", dmap=DESIGN["maps"]),
        # the chunks' job times, for the cost table (runs and impacts per second)
        cost=[
            f"benchmarks/design_chunk/{m}-{i}.tsv"
            for m in DESIGN["maps"]
            for i in range(RESOLUTION["design"]["chunks"])
        ],
    output:
        csv="results/tables/design_robust.csv",
        md="results/tables/design_robust.md",
        cost="results/tables/design_cost.md",
    log:
        "logs/tables/design_robust.log",
    conda:
        "../envs/vibroimpact.yaml"
    params:
        budget=DESIGN["budget"],
        table_betas=DESIGN["table_betas"],
        code=code("design_robust.py"),
    script:
        "../scripts/design_robust.py"
