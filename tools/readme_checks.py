"""Refresh README.md's check section from results/checks/paper_values.csv (after `snakemake check`):
the summary sentence, the table of rows that are not a plain pass, and the full table.

    .venv/bin/python tools/readme_checks.py
"""

import re
from pathlib import Path

import pandas as pd

from vibroimpact.outputs.checks import markdown

ROOT = Path(__file__).resolve().parents[1]
readme = ROOT / "README.md"
df = pd.read_csv(ROOT / "results/checks/paper_values.csv", keep_default_na=False)


def _number(x):
    try:
        return float(x)
    except ValueError:
        return x


for col in ("paper", "computed", "tolerance"):  # mixed columns come back as text: numbers print as numbers
    df[col] = df[col].map(_number)
full = markdown(df)
summary = full.strip().splitlines()[-1]  # "Summary: ..."
rows = markdown(df[df["status"] != "pass"]).strip().splitlines()[:-2]  # without its own summary
text = readme.read_text()
start = text.index("## Checks against the paper")
end = text.index("The second is the **figure regeneration check**")
section = text[start:end]
section = re.sub(r"Summary: [^\n]*?\.(?=\n\n\| item)", summary, section, count=1)
head, rest = section.split("\n\n| item | paper |", 1)
details = rest[rest.index("<details>"):]
details_head = details[:details.index("| item | paper |")]
new = (head + "\n\n" + "\n".join(rows) + "\n\n" + details_head + full.rstrip("\n") + "\n\n</details>\n\n")
readme.write_text(text[:start] + new + text[end:])
print(summary)
