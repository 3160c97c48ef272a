# Caption orbits: exact simulation from the paper's initial conditions, with the attractor found.


rule caption_orbit:
    output:
        "results/orbits/caption-{name}.nc",
    params:
        p=lambda wc: caption_params(wc.name),
    conda:
        "../envs/vibroimpact.yaml"
    log:
        "logs/orbits/caption-{name}.log",
    benchmark:
        "benchmarks/orbits/caption-{name}.tsv"
    script:
        "../scripts/caption_orbit.py"


rule caption_summary:
    input:
        expand("results/orbits/caption-{name}.nc", name=CAPTIONS),
    output:
        nc="results/orbits/captions.nc",
        md="results/tables/captions.md",
    params:
        names=list(CAPTIONS),
        stated={n: c["motion"] + (f" period-{c['period']}" if "period" in c else "") for n, c in CAPTIONS.items()},
    conda:
        "../envs/vibroimpact.yaml"
    log:
        "logs/orbits/captions.log",
    script:
        "../scripts/caption_summary.py"
