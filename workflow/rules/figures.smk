# Figures: one script per scene, drawn only from saved datasets.


rule scene_figure:
    input:
        lambda wc: expand("results/orbits/caption-{name}.nc", name=config["scenes"][wc.scene]["captions"]),
    output:
        pdf="results/figures/{scene}.pdf",
        png="results/figures/{scene}.png",
        data="results/figures/data/{scene}.nc",
    conda:
        "../envs/vibroimpact.yaml"
    log:
        "logs/figures/{scene}.log",
    script:
        "../scripts/scene_figure.py"
