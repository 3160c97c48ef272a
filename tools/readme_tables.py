"""Refresh the tables README.md quotes from the workflow's own tables: every block between
``<!-- table: PATH -->`` and ``<!-- end table -->`` is replaced by the file PATH (relative to the
repository), as the last run wrote it.

    .venv/bin/python tools/readme_tables.py
"""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
readme = ROOT / "README.md"
text = readme.read_text()
pattern = re.compile(r"(<!-- table: (\S+) -->\n)(.*?)(<!-- end table -->)", re.S)


def _fill(m):
    body = (ROOT / m.group(2)).read_text().strip("\n")
    return f"{m.group(1)}{body}\n{m.group(4)}"


new, n = pattern.subn(_fill, text)
readme.write_text(new)
print(f"{n} tables refreshed")
