# Figures of the analytic branches with simulated points (Figures 5 and 6; vibroimpact.outputs.registry).


rule fig2:
    input:
        branches=scene_branch_files("fig2"),
        sims=scene_branch_files("fig2", kind="sim"),
    output:
        **figure_formats("results/figures/fig2"),
        png=report(
            "results/figures/fig2.png",
            caption=figure_caption("fig2"),
            category=figure_category("fig2"),
        ),
        data="results/figures/data/fig2.nc",
    log:
        "logs/figures/fig2.log",
    benchmark:
        "benchmarks/fig2/fig2.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        scene=BRANCH_SCENES["fig2"],
        k_s=config["physics"]["M"]
        * config["physics"]["omega"] ** 2
        / (config["physics"]["F"] * math.pi**2),
        code=code("branch_figure.py"),
    script:
        "../scripts/branch_figure.py"


rule fig3:
    input:
        branches=scene_branch_files("fig3"),
        sims=scene_branch_files("fig3", kind="sim"),
    output:
        **figure_formats("results/figures/fig3"),
        png=report(
            "results/figures/fig3.png",
            caption=figure_caption("fig3"),
            category=figure_category("fig3"),
        ),
        data="results/figures/data/fig3.nc",
    log:
        "logs/figures/fig3.log",
    benchmark:
        "benchmarks/fig3/fig3.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        scene=BRANCH_SCENES["fig3"],
        k_s=config["physics"]["M"]
        * config["physics"]["omega"] ** 2
        / (config["physics"]["F"] * math.pi**2),
        code=code("branch_figure.py"),
    script:
        "../scripts/branch_figure.py"
