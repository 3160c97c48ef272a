# Which of the paper's published numbers and claims are reproduced (results/checks/paper_values.csv).


rule check:
    input:
        captions="results/orbits/captions.nc",
        table1="results/tables/table1.csv",
        bis=sweep_path("figBiS", "-transitions"),
        branches_s=[energy_path("branch", b, "BT", "s") for b in BRANCH_SCENES["fig3"]["betas"]],
        branches_F=[energy_path("branch", SWEEPS[p]["beta"], "BT", "F") for p in config["energy"]["design"]["F"]
                    if p in {q for f in config["energy"]["figures"].values() for q in f["panels"]}],
        sweeps=[energy_path("sweep", SWEEPS[p]["beta"], p) for v in ("s", "F") for p in config["energy"]["design"][v]],
    output:
        csv="results/checks/paper_values.csv",
        md="results/checks/paper_values.md",
    params:
        known=config["checks"]["known"],
    conda:
        "../envs/vibroimpact.yaml"
    log:
        "logs/checks/paper_values.log",
    script:
        "../scripts/check.py"
