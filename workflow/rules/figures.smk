# Figures: one script per scene, drawn only from saved datasets.


rule scene_figure:
    input:
        lambda wc: expand(
            "results/orbits/caption-{name}.nc",
            name=config["scenes"][wc.scene]["captions"],
        ),
    output:
        **figure_formats("results/figures/{scene}"),
        png=report(
            "results/figures/{scene}.png",
            caption="../report/scene.rst",
            category="Paper figures",
        ),
        data="results/figures/data/{scene}.nc",
    log:
        "logs/figures/{scene}.log",
    benchmark:
        "benchmarks/scene_figure/{scene}.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        code=code("scene_figure.py"),
    script:
        "../scripts/scene_figure.py"
