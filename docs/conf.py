"""Sphinx configuration of the chaplygin documentation (MyST pages, myst-nb notebooks, Furo).

Build: ``.venv/bin/sphinx-build -W -b html docs docs/_build/html`` (the ``docs`` extra). The
claims catalogue is generated from ``chaplygin verify --json``: from the file that
``CHAPLYGIN_VERIFY_JSON`` names (CI passes the output of its verify step), or by running it.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent / "_ext"))

project = "chaplygin"
author = "chaplygin developers"
copyright = "2026, chaplygin developers"  # noqa: A001 (Sphinx's name)

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "sphinx.ext.napoleon",
    "chaplygin_docs",
]
source_suffix = {".md": "myst-nb", ".rst": "restructuredtext"}
exclude_patterns = [
    "_build",
    "_ext",
    "reference/_entries.md",
    "Thumbs.db",
    ".DS_Store",
    "**.ipynb_checkpoints",
]

myst_enable_extensions = ["colon_fence", "deflist"]
myst_heading_anchors = 4

# notebooks run at every build, each in a fresh kernel; one error fails the build
nb_execution_mode = "force"
nb_execution_timeout = 120
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_merge_streams = True

autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_default_options = {"members": True, "undoc-members": False}
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_rtype = False
napoleon_use_ivar = True  # a class's Attributes as fields: autodoc lists the members themselves

html_theme = "furo"
html_title = "chaplygin"
html_static_path = ["_static"]
html_favicon = "_static/favicon.svg"
