#!/usr/bin/env python3
"""Rewrite the generated tables of the open-questions studies (blocks
<!-- open-questions[:STUDY] [t=T] --> ... <!-- end -->) in README.md and docs/open_questions.md
from the stored studies in studies/open_questions. Nothing is computed; run it after a study was
continued. tests/python/test_open_questions.py checks the pages are up to date.

    .venv/bin/python tools/update-open-tables.py [PAGE ...]
"""
import pathlib
import sys

from fputlab.figures_open import generated_tables

ROOT = pathlib.Path(__file__).resolve().parents[1]
pages = sys.argv[1:] or [ROOT / "README.md", ROOT / "docs" / "open_questions.md"]
for page in map(pathlib.Path, pages):
    old = page.read_text()
    new = generated_tables(old, ROOT / "studies" / "open_questions")
    if new != old:
        page.write_text(new)
        print(f"{page}: updated")
