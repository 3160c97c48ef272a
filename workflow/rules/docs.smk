# The documentation site (docs/, Sphinx): the user guide, the tutorials run at build time, the paper's
# figures with their captions and check results, speed and accuracy, and the API reference, built from
# the repository and from the results of the targets below, warnings as errors.
import glob


rule docs:
    input:
        rules.all.input,
        rules.check.input,
        rules.bench.input,
        rules.bifurcation.input,
        rules.design_maps.input,
        # the speed-and-accuracy page's numbers
        rules.speed_summary.output,
        conf="docs/conf.py",
        # its own sources, so that an edited page or tutorial rebuilds it (not the pages it generates)
        sources=sorted(
            set(glob.glob("docs/**/*.md", recursive=True) + glob.glob("docs/*.rst"))
            - set(glob.glob("docs/tutorials/**", recursive=True))
            - set(glob.glob("docs/_generated/**", recursive=True))
            - {"docs/paper.md"}
        )
        + glob.glob("docs/_ext/*.py")
        + glob.glob("examples/*")
        + glob.glob("workflow/report/*.rst")
        # the workflow page's rule graph is drawn from the rules
        + ["Snakefile"]
        + glob.glob("workflow/rules/*.smk"),
    output:
        "results/docs/html/index.html",
    log:
        build="logs/docs/docs.log",
        warnings="logs/docs/docs.warnings.txt",
    benchmark:
        "benchmarks/docs/docs.tsv"
    conda:
        "../envs/vibroimpact.yaml"
    params:
        source=lambda wc, input: os.path.dirname(input.conf),
        html=lambda wc, output: os.path.dirname(output[0]),
        doctrees=lambda wc, output: os.path.join(
            os.path.dirname(os.path.dirname(output[0])), "doctrees"
        ),
        code=code(),  # the API reference imports every module of the package
    script:
        "../scripts/docs.py"
