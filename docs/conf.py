"""Sphinx configuration of the fputlab reference (built by `./dev docs`, warnings are errors)."""
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

project = "fputlab"
author = "The fputlab developers"
copyright = "the fputlab developers; GPL-3.0-or-later"
# the version is defined once, in meson.build
release = version = re.search(r"project\([^)]*?version:\s*'([^']+)'",
                              (ROOT / "meson.build").read_text(), re.S).group(1)

extensions = ["sphinx.ext.autodoc", "sphinx.ext.mathjax", "numpydoc"]
source_suffix = {".rst": "restructuredtext"}
exclude_patterns = ["_build", "figures", "**/*.md"]
root_doc = "index"

autodoc_default_options: dict = {}   # every directive in python.rst names its members
autodoc_member_order = "bysource"
autodoc_typehints = "none"          # numpydoc sections carry the types
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False

html_theme = "alabaster"
html_static_path: list[str] = []
html_theme_options = {"description": "FPUT lattices, ordered and disordered", "fixed_sidebar": True}
