"""Sphinx configuration of vibroimpact's documentation: built from the repository and from the
workflow's results (``snakemake --cores 2 docs``), warnings as errors."""

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE / "_ext"))

import vibroimpact  # noqa: E402

project = "vibroimpact"
author = "The vibroimpact developers"
copyright = "2026, the vibroimpact developers (BSD-3-Clause)"
version = release = vibroimpact.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
    "vibroimpact_pages",
    "vibroimpact_rulegraph",  # the workflow page's rule graph and target list, from the Snakefile
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "tutorials/*.ipynb", "tutorials/*.py", "tutorials/*.zip", "tutorials/*.md5",
                    "tutorials/*.json"]
myst_enable_extensions = ["dollarmath", "colon_fence"]
myst_heading_anchors = 3
suppress_warnings = ["myst.header"]  # pages moved from one long README start their levels at ##

# the API reference: one page per public name, from its numpydoc docstring
autosummary_generate = True
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
# every public docstring has a summary line and documents its parameters and what it returns
numpydoc_validation_checks = {"SS01", "PR01", "RT01"}
# (the records a call returns, Orbit, Attractor, Lyapunov and PhysicalScales, document their fields as Attributes:
# nobody constructs them, so they have no Parameters to document; members are documented on the class)
numpydoc_validation_exclude = {r"\.__init__$", r"^vibroimpact\.(Orbit|Attractor|Lyapunov|PhysicalScales)$",
                               r"Params\.", r"Orbit\.", r"Attractor\.", r"Lyapunov\.", r"Membrane\.", r"PhysicalScales\."}

# tutorials: examples/*.py, executed at every build (a failing example fails the build)
sphinx_gallery_conf = {
    "examples_dirs": str(HERE.parent / "examples"),
    "gallery_dirs": "tutorials",
    "filename_pattern": r"/tutorial_",
    "abort_on_example_error": True,
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "show_memory": False,
    "plot_gallery": "True",
}

html_theme = "pydata_sphinx_theme"
html_title = f"vibroimpact {version}"
html_theme_options = {"navigation_with_keys": False, "show_toc_level": 2}
html_static_path = []
nitpicky = False
