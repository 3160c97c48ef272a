# Figures and tables of the output voltage (computed beside each branch and sweep, rules branch and
# sweep): Figures 2 and 9 and the design guidance.


rule energy_figure:
    input:
        energies=lambda wc: [
            f
            for p in config["energy"]["figures"][wc.efig]["panels"]
            for f in energy_panel_inputs(p)
        ],
        sweeps=lambda wc: [
            sweep_path(p) for p in config["energy"]["figures"][wc.efig]["panels"]
        ],
        # each sweep's located transitions: its 1:1 exit, where its 1:1 motion leaves the 1:1 family
        transitions=lambda wc: [
            sweep_path(p, "-transitions")
            for p in config["energy"]["figures"][wc.efig]["panels"]
        ],
        # the continued 1:1 and 2:1 branches: d_graz (the 2:1 fold) and G1
        orbits=lambda wc: [
            branch_path("orbit", SWEEPS[p]["beta"], w, SWEEPS[p]["vary"])
            for p in config["energy"]["figures"][wc.efig]["panels"]
            for w in ("BT", "BBT")
            if w in WORDS
        ],
    output:
        **figure_formats("results/figures/{efig}"),
        png=report(
            "results/figures/{efig}.png",
            caption=figure_caption("energy_figure"),
            category=figure_category("energy_figure"),
        ),
        data="results/figures/data/{efig}.nc",
    log:
        "logs/figures/{efig}.log",
    benchmark:
        "benchmarks/energy_figure/{efig}.tsv"
    wildcard_constraints:
        efig="|".join(config["energy"]["figures"]),
    priority: 10  # long figures: drawn as soon as their data are, so that short jobs fill the other core to the end
    conda:
        "../envs/vibroimpact.yaml"
    params:
        panels=lambda wc: config["energy"]["figures"][wc.efig]["panels"],
        velocities=lambda wc: config["energy"]["figures"][wc.efig].get(
            "velocities", False
        ),
        words=[w for w in ("BT", "BBT") if w in WORDS],
        code=code("energy_figure.py"),
    script:
        "../scripts/energy_figure.py"


rule design:
    input:
        s=[
            energy_path("sweep", SWEEPS[p]["beta"], p)
            for p in config["energy"]["design"]["s"]
        ],
        F=[
            energy_path("sweep", SWEEPS[p]["beta"], p)
            for p in config["energy"]["design"]["F"]
        ],
    output:
        **figure_formats("results/figures/design"),
        csv="results/tables/design.csv",
        # where each average rises and falls along each sweep (the design figure's direction)
        trends="results/tables/design_trends.csv",
        md="results/tables/design.md",
        png=report(
            "results/figures/design.png",
            caption=figure_caption("design"),
            category=figure_category("design"),
        ),
        data="results/figures/data/design.nc",
    log:
        "logs/tables/design.log",
    benchmark:
        "benchmarks/design/design.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        code=code("design.py"),
    script:
        "../scripts/design.py"


rule study_figure:
    input:
        energies=lambda wc: [
            f"results/energy/beta-{wc.beta}_r-{wc.r}/study_s.nc",
            *[
                f"results/energy/beta-{wc.beta}_r-{wc.r}/orbit-{w}_vary-s.nc"
                for w in ("BT", "BBT")
                if w in WORDS
            ],
        ],
        # a list, as energy_figure.py reads one sweep per panel
        sweeps=["results/sweeps/beta-{beta}_r-{r}/study_s.nc"],
        transitions=["results/sweeps/beta-{beta}_r-{r}/study_s-transitions.nc"],
        orbits=lambda wc: [
            f"results/branches/beta-{wc.beta}_r-{wc.r}/orbit-{w}_vary-s.nc"
            for w in ("BT", "BBT")
            if w in WORDS
        ],
    output:
        **figure_formats("results/studies/beta-{beta}_r-{r}/study"),
        png="results/studies/beta-{beta}_r-{r}/study.png",
        data="results/studies/beta-{beta}_r-{r}/study-figure-data.nc",
    log:
        "logs/studies/beta-{beta}_r-{r}.log",
    benchmark:
        "benchmarks/study_figure/beta-{beta}_r-{r}.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        panels=["study_s"],
        velocities=True,
        words=[w for w in ("BT", "BBT") if w in WORDS],
        code=code("energy_figure.py"),
    script:
        "../scripts/energy_figure.py"
