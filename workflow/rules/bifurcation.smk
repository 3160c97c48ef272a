# Bifurcation set: the branches' period doublings, folds and grazing points followed as curves in the
# regime maps' parameter planes and in non-dimensional planes (vibroimpact.analysis.bifurcation), drawn over
# brute-force maps of the same planes.


rule bifurcation:
    input:
        figure_targets("bifurcation", formats=["png"]),
        ["results/tables/bistable_band.md"] if "s_beta" in config["maps"] else [],


rule bistable_band:
    input:
        "results/bifurcation/s_beta.nc",
    output:
        nc="results/bifurcation/bistable_band.nc",
        md="results/tables/bistable_band.md",
    log:
        "logs/bifurcation/bistable_band.log",
    benchmark:
        "benchmarks/bistable_band/bistable_band.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        betas=config["bifurcation"]["bistable_betas"],
        code=code("bistable_band.py"),
    script:
        "../scripts/bistable_band.py"


rule bifurcation_set:
    input:
        # the analytic branches the curves start from: their located critical points
        lambda wc: [
            branch_path("orbit", config["bifurcation"]["beta"], w)
            for w in config["bifurcation"]["words"]
        ],
    output:
        "results/bifurcation/{map}.nc",
    log:
        "logs/bifurcation/{map}.log",
    benchmark:
        "benchmarks/bifurcation_set/{map}.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        map=lambda wc: ALL_MAPS[wc.map],
        device=DEVICE_SPEC,
        bifurcation=config["bifurcation"],
        code=code("bifurcation_set.py"),
    script:
        "../scripts/bifurcation_set.py"


rule family_exit_curve:
    output:
        "results/bifurcation/{map}-exit.nc",
    log:
        "logs/bifurcation/{map}-exit.log",
    benchmark:
        "benchmarks/family_exit_curve/{map}.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        spec=lambda wc: (
            ALL_MAPS[wc.map]
            if wc.map in config["maps"]
            else {"beta": config["bifurcation"]["beta"]} | ALL_MAPS[wc.map]
        ),
        device=DEVICE_SPEC,
        grid=RESOLUTION["map_grid"],
        lines=config["bifurcation"]["exit_lines"],
        xtol=config["sweeps"]["locate"]["xtol"],
        code=code("family_exit_curve.py"),
    script:
        "../scripts/family_exit_curve.py"


rule fig_bifurcation_set:
    input:
        map=lambda wc: map_path(wc.map),
        curves="results/bifurcation/{map}.nc",
        # the 1:1 exit over the plane (the 1:1 motion followed down leaves its family)
        exit="results/bifurcation/{map}-exit.nc",
    output:
        **figure_formats("results/figures/bifurcation_set_{map}"),
        png=report(
            "results/figures/bifurcation_set_{map}.png",
            caption=figure_caption("fig_bifurcation_set"),
            category=figure_category("fig_bifurcation_set"),
        ),
        data="results/figures/data/bifurcation_set_{map}.nc",
        # the map's simulated boundaries, each on a curve or not and why (vibroimpact.analysis.bifurcation.map_boundaries)
        boundaries="results/bifurcation/{map}-boundaries.nc",
    log:
        "logs/figures/bifurcation_set_{map}.log",
    benchmark:
        "benchmarks/fig_bifurcation_set/{map}.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        code=code("fig_bifurcation_set.py"),
    script:
        "../scripts/fig_bifurcation_set.py"
