# Caption orbits: exact simulation from the paper's initial conditions, with the attractor found.


rule caption_orbits:
    # one job for all captions: each takes a fraction of a second, less than starting a job
    output:
        expand("results/orbits/caption-{name}.nc", name=CAPTIONS),
    log:
        "logs/orbits/caption-orbits.log",
    benchmark:
        "benchmarks/orbits/caption-orbits.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        p=[caption_params(n) for n in CAPTIONS],
        code=code("caption_orbit.py"),
    script:
        "../scripts/caption_orbit.py"


rule caption_summary:
    input:
        expand("results/orbits/caption-{name}.nc", name=CAPTIONS),
    output:
        nc="results/orbits/captions.nc",
        md="results/tables/captions.md",
    log:
        "logs/orbits/captions.log",
    benchmark:
        "benchmarks/caption_summary/captions.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        names=list(CAPTIONS),
        stated={
            n: c["motion"] + (f" period-{c['period']}" if "period" in c else "")
            for n, c in CAPTIONS.items()
        },
        code=code("caption_summary.py"),
    script:
        "../scripts/caption_summary.py"
