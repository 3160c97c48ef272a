# `check`: which of the paper's published numbers and claims are reproduced
# (results/checks/paper_values.csv), and whether every figure draws the same data as its committed
# reference (results/checks/figures.csv).


rule check:
    input:
        "results/checks/paper_values.csv",
        "results/checks/figures.csv",


rule check_paper_values:
    input:
        captions="results/orbits/captions.nc",
        table1="results/tables/table1.csv",
        bis=sweep_path("figBiS", "-transitions"),
        sims=scene_branch_files("fig2", kind="sim"),
        branches_s=[
            energy_path("branch", b, "BT", "s") for b in BRANCH_SCENES["fig3"]["betas"]
        ],
        branches_F=[
            energy_path("branch", SWEEPS[p]["beta"], "BT", "F")
            for p in config["energy"]["design"]["F"]
            if p
            in {q for f in config["energy"]["figures"].values() for q in f["panels"]}
        ],
        sweeps=[
            energy_path("sweep", SWEEPS[p]["beta"], p)
            for v in ("s", "F")
            for p in config["energy"]["design"][v]
        ],
        # the same sweeps' motions (their windows of events)
        motion_sweeps=[
            sweep_path(p) for v in ("s", "F") for p in config["energy"]["design"][v]
        ],
        # the 2:1 branches whose curve order the captions of Figures 2, 5 and 9 state
        order_orbits=[
            branch_path("orbit", b, "BBT") for b in BRANCH_SCENES["fig2"]["betas"]
        ],
        # d_graz along each incline's length and force sweep, and the 1:1 branches
        d_graz="results/tables/d_graz.csv",
        bt_branches=[
            branch_path("orbit", b, "BT")
            for b in BRANCH_SCENES["fig3"]["betas"]
            if "BT" in WORDS
        ],
        order_energy=sorted(
            {
                energy_path("branch", SWEEPS[p]["beta"], "BBT", "s")
                for f in config["energy"]["figures"].values()
                for p in f["panels"]
                if SWEEPS[p]["vary"] == "s"
            }
        ),
    output:
        csv=report(
            "results/checks/paper_values.csv",
            caption="../report/paper_values.rst",
            category="Checks",
        ),
        md="results/checks/paper_values.md",
    log:
        "logs/checks/paper_values.log",
    benchmark:
        "benchmarks/check_paper_values/paper_values.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        known=config["checks"]["known"],
        d_graz_scenes={p: SWEEPS[p] for p in D_GRAZ_SWEEPS},
        # another device: the paper's numbers are its device's, not compared
        device=CFG.device.name,
        paper_device=CFG.paper_device,
        code=code("check.py"),
    script:
        "../scripts/check.py"


# One figure against its committed reference (snakemake results/checks/figures/fig2.csv checks one);
# fails, naming the arrays, when the figure moved.
rule check_figure:
    input:
        data="results/figures/data/{fig}.nc",
        # the committed reference; a missing one is reported by the check (not a missing input)
        reference=lambda wc: [
            f for f in [figure_reference(wc.fig)] if os.path.exists(f)
        ],
    output:
        "results/checks/figures/{fig}.csv",
    log:
        "logs/checks/figures/{fig}.log",
    wildcard_constraints:
        fig="|".join(FIGURES),
    conda:
        "../envs/vibroimpact.yaml"
    params:
        **{k: v for k, v in config["figure_checks"].items() if k != "reference_dir"},
        reference=lambda wc: figure_reference(wc.fig),
        # each array's measured conditioning, kept with the references (target figure_conditioning)
        conditioning=f"{config['figure_checks']['reference_dir']}/conditioning.csv",
        code=code("check_figure.py"),
    script:
        "../scripts/check_figure.py"


rule check_figures:
    input:
        # the committed references are the paper's device's: another device's figures are not compared
        expand("results/checks/figures/{fig}.csv", fig=FIGURES)
        if CFG.paper_device
        else [],
    output:
        csv=report(
            "results/checks/figures.csv",
            caption="../report/figures_check.rst",
            category="Checks",
        ),
        md="results/checks/figures.md",
    log:
        "logs/checks/figures.log",
    conda:
        "../envs/vibroimpact.yaml"
    params:
        rtol=config["figure_checks"]["rtol"],
        atol=config["figure_checks"]["atol"],
        conditioning=f"{config['figure_checks']['reference_dir']}/conditioning.csv",
        device=CFG.device.name,
        figures=FIGURES,
        code=code("check_figures.py"),
    script:
        "../scripts/check_figures.py"


# How well each figure array is determined: the figure data recomputed in scratch copies under
# perturbations that stand for another machine (another libm, other OpenBLAS kernels, the inputs moved by a
# few ulps), each array's spread and whether its declared rule passes it (vibroimpact.outputs.conditioning).
# Slow (a whole regeneration per perturbation): run it before accepting new references.
rule figure_conditioning:
    input:
        expand("results/figures/data/{fig}.nc", fig=FIGURES),
    output:
        csv="results/checks/conditioning.csv",
        summary="results/checks/conditioning_summary.csv",
        md="results/checks/conditioning.md",
    log:
        "logs/checks/figure_conditioning.log",
    benchmark:
        "benchmarks/figure_conditioning/figure_conditioning.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        figures=FIGURES,
        rtol=config["figure_checks"]["rtol"],
        atol=config["figure_checks"]["atol"],
        optional=config["figure_checks"]["optional_peers"],
        scratch="results/conditioning",
        code=code("figure_conditioning.py"),
    script:
        "../scripts/figure_conditioning.py"


# Deliberately accept the current figures: copy their data, and their measured conditioning, over the
# committed references.
rule update_figure_references:
    input:
        data=expand("results/figures/data/{fig}.nc", fig=FIGURES),
        conditioning="results/checks/conditioning.csv",
        summary="results/checks/conditioning_summary.csv",
    log:
        "logs/checks/update_figure_references.log",
    conda:
        "../envs/vibroimpact.yaml"
    params:
        reference_dir=config["figure_checks"]["reference_dir"],
        code=code("update_figure_references.py"),
    script:
        "../scripts/update_figure_references.py"
