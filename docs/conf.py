"""Sphinx configuration of the fputlab documentation (built by `./dev docs`, warnings are errors).

docs/README.md says what is where and how to add a page, a module or an example. In short:
Markdown guides by myst-parser (``$...$`` math); the Python API one page per module, generated
by autosummary from the list in ``api/index.rst``; the C API page written from the headers by
``tools/gen_c_api_docs.py``; the tutorial (``docs/tutorial``) and the gallery (``examples/``) run
at build time by sphinx-gallery, except the figure scripts in `PRERENDERED`, which show the
gallery PNG that ``fputlab figures`` made; the CLI page generated from the parser
(sphinx-argparse); the references from ``references.bib`` (sphinxcontrib-bibtex).
"""
import os
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS / "_ext"))      # gallery_figures: the gallery's hooks

project = "fputlab"
author = "The fputlab developers"
copyright = "the fputlab developers; GPL-3.0-or-later"
# the version is defined once, in meson.build
release = version = re.search(r"project\([^)]*?version:\s*'([^']+)'",
                              (ROOT / "meson.build").read_text(), re.S).group(1)

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    # MathJax from the package, copied into the site: the maths renders offline too
    "sphinx-mathjax-offline",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "sphinxarg.ext",
    "sphinxcontrib.bibtex",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
# figures/: the gallery's PNGs (shown by the pages, not pages); README.md: for GitHub readers
exclude_patterns = ["_build", "figures", "README.md", "tutorial", "_ext", "auto_examples/*.ipynb",
                    "auto_tutorial/*.ipynb", "**/*.py.md5", "**/*.zip"]
templates_path = ["_templates"]

# ---- Markdown (myst-parser) -------------------------------------------------------------------
myst_enable_extensions = ["dollarmath", "amsmath", "deflist"]
myst_heading_anchors = 3          # links like hdf5.md#checkpoint-files resolve
# "python notest" blocks are shown as Python but not run by tests/python/test_docs_code.py
myst_fence_as_directive: list[str] = []

# ---- API reference (autodoc, autosummary, numpydoc) -------------------------------------------
autosummary_generate = True
autosummary_ignore_module_all = False     # a module's members are its __all__
autosummary_imported_members = False
autodoc_default_options: dict = {}
autodoc_member_order = "bysource"
autodoc_typehints = "none"                # numpydoc sections carry the types
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
numpydoc_validation_checks: set[str] = set()

# ---- bibliography -----------------------------------------------------------------------------
bibtex_bibfiles = ["references.bib"]
bibtex_default_style = "plain"

# ---- tutorial and gallery (sphinx-gallery) ----------------------------------------------------
#: figure scripts whose quick run takes longer than the docs build can afford (CI budget: the
#: whole build in ~3 min on 2 cores): not run by the build; their page shows the gallery PNG
#: that `fputlab figures --out-dir docs/figures` made (also their thumbnail).
PRERENDERED = {
    "fig04_galerkin.py": "fig04_galerkin.png",                   # ~15 s alone on 2 cores
    "fig11_chaos_homogeneous.py": "fig11_chaos_homogeneous.png", # ~10 s
    "fig12_14_chaos_disorder.py": "fig12_chaos_N4_8_16.png",     # minutes (the chaos study)
}

sphinx_gallery_conf = {
    "examples_dirs": [str(DOCS / "tutorial"), str(ROOT / "examples")],
    "gallery_dirs": ["auto_tutorial", "auto_examples"],
    # run every example except the pre-rendered ones
    "filename_pattern": r"/(?!(" + "|".join(re.escape(n) for n in PRERENDERED) + r")$)[^/]+\.py$",
    "ignore_pattern": r"__init__\.py|/c/",
    "reset_argv": "gallery_figures.figure_script_argv",
    "image_scrapers": ("gallery_figures.scrape_written_figures",),
    "within_subsection_order": "FileNameSortKey",
    "download_all_examples": False,
    "remove_config_comments": True,
    "abort_on_example_error": True,       # an example that fails fails the build
    "matplotlib_animations": False,
    "show_memory": False,
    "min_reported_time": 1,
    # a block ending in ax.set_title(...) shows its figure, not "Text(0.5, 1.0, ...)"
    "ignore_repr_types": r"matplotlib\.(text|axes|figure|lines|legend)",
}
os.environ.setdefault("MPLBACKEND", "Agg")


def _prerendered_image(app, docname, source):
    """Put the pre-rendered PNG on the page of an example that the build does not run."""
    if not docname.startswith("auto_examples/"):
        return
    script = Path(docname).name + ".py"
    if script in PRERENDERED:
        pngs = [PRERENDERED[script]]
        if script.startswith("fig12_14"):
            pngs = ["fig12_chaos_N4_8_16.png", "fig13_chaos_N32_64.png",
                    "fig14_chaotic_fraction.png"]
        images = "".join(f"\n.. image:: /figures/{png}\n   :width: 100%\n   :alt: {png}\n"
                         for png in pngs)
        made = ("drawn from the full study to :math:`t = 10^8` in ``studies/fig12_14`` by "
                "``fputlab figures --out-dir docs/figures --work-dir studies/fig12_14``"
                if script.startswith("fig12_14") else
                "made by ``fputlab figures --out-dir docs/figures`` with the quick defaults")
        note = ("\n.. note:: Not run when these pages are built (it takes longer than the docs "
                f"build may): the figure is the gallery's, {made}.\n")
        # after the example's title and introduction, before the code
        text = source[0]
        cut = text.find(".. code-block:: Python")
        if cut < 0:
            cut = len(text)
        source[0] = text[:cut] + note + images + "\n" + text[cut:]


# ---- HTML -------------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = f"fputlab {release}"
# pages without siblings need no section navigation: the room goes to their code
html_sidebars = {"_generated/c_api": [], "cli": [], "index": [], "install": [],
                 "references": [], "changelog": [], "auto_tutorial/*": []}
html_static_path = ["_static"]
html_css_files = ["fputlab.css"]
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "navbar_align": "left",
    "header_links_before_dropdown": 4,
    "footer_start": ["copyright"],
    "footer_end": ["sphinx-version"],
}
html_context = {"default_mode": "light"}
html_show_sourcelink = False


def setup(app):
    app.connect("source-read", _prerendered_image)
