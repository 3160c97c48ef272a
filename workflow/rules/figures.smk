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
            caption=figure_caption("scene_figure"),
            category=figure_category("scene_figure"),
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


# A figure added to the registry of figures (vibroimpact.outputs.registry) with rule "registry_figure": its plot
# function called on the datasets its row names; its caption is the row's template, rendered by common.smk.
# The rule exists where a row names it.
if REGISTRY_FIGURES:

    rule registry_figure:
        input:
            lambda wc: list(REGISTRY_FIGURES[wc.rfig].inputs),
        output:
            **figure_formats("results/figures/{rfig}"),
            png=report(
                "results/figures/{rfig}.png",
                caption="../report/registry_figure.rst",
                category="Registered figures",
            ),
            data="results/figures/data/{rfig}.nc",
        log:
            "logs/figures/{rfig}.log",
        benchmark:
            "benchmarks/registry_figure/{rfig}.tsv"
        wildcard_constraints:
            rfig="|".join(REGISTRY_FIGURES),
        conda:
            "../envs/vibroimpact.yaml"
        params:
            plot=lambda wc: REGISTRY_FIGURES[wc.rfig].plot,
            code=code("registry_figure.py"),
        script:
            "../scripts/registry_figure.py"
