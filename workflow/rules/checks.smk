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
        # the 2:1 branches whose curve order the captions of Figs 0, 2 and 5 state
        order_orbits=[
            branch_path("orbit", b, "BBT") for b in BRANCH_SCENES["fig2"]["betas"]
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
    script:
        "../scripts/check.py"


rule check_figures:
    input:
        data=expand("results/figures/data/{fig}.nc", fig=FIGURES),
        # committed references; a missing one is reported by the check (not a missing input)
        reference=[f for f in FIGURE_REFERENCES if os.path.exists(f)],
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
        **{k: v for k, v in config["figure_checks"].items() if k != "reference_dir"},
        figures=FIGURES,
        references=FIGURE_REFERENCES,
    script:
        "../scripts/check_figures.py"


# Deliberately accept the current figures: copy their data over the committed references.
rule update_figure_references:
    input:
        expand("results/figures/data/{fig}.nc", fig=FIGURES),
    log:
        "logs/checks/update_figure_references.log",
    conda:
        "../envs/vibroimpact.yaml"
    params:
        reference_dir=config["figure_checks"]["reference_dir"],
    script:
        "../scripts/update_figure_references.py"
