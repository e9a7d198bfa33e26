"""A new system added by following docs/adding-a-system.md shows up green in `harness check` and in the report,
with no file in harness/, tests/ or models/ touched: the system lives in a temporary folder on the catalogue's
search path (HARNESS_MODELS_PATH, here set on the running catalogue) and is gone afterwards."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import models
from harness import cli

ROOT = Path(__file__).resolve().parent.parent
NAME = "throwaway_rod"


def documented_module() -> str:
    """The complete module at the end of docs/adding-a-system.md, renamed: the catalogue's models/pendulum_rod.py
    as it stands (the page prints the file; they must not drift apart)."""
    text = (ROOT / "docs" / "adding-a-system.md").read_text()
    code = re.findall(r"```python\n(.*?)```", text, re.S)[-1]
    assert code == (ROOT / "models" / "pendulum_rod.py").read_text()
    return code.replace('name="pendulum_rod"', f'name="{NAME}"')


def test_scaffold_fill_check_report(user_models, tmp_path, capsys):
    search_path = user_models
    before = sorted(p.name for p in (ROOT / "models").iterdir())
    # 1. scaffold: a conformant model with a checklist
    assert cli.main(["new", NAME, "--dir", str(search_path)]) == 0
    scaffolded = (search_path / f"{NAME}.py").read_text()
    assert "Checklist" in scaffolded and "CLAIMS" in scaffolded and "SCENES" in scaffolded
    # existing names and invalid identifiers are refused with one line
    models.reload()
    for bad in (NAME, "pendulum", "Not-A-Name", "class"):
        capsys.readouterr()
        assert cli.main(["new", bad, "--dir", str(search_path)]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and err[0].startswith("error: new:"), err
    # 2. fill it in as the document does
    (search_path / f"{NAME}.py").write_text(documented_module())
    models.reload()
    sys.modules.pop(f"models.{NAME}", None)
    assert models.get(NAME).title == "Pendulum rod"
    capsys.readouterr()
    assert cli.main(["list"]) == 0   # beside its status, the folder it comes from; the lecture's own say nothing
    listed = {line.split()[0]: line for line in capsys.readouterr().out.splitlines()}
    assert listed[NAME].endswith(f"modeled, outside the lecture's catalogue: {search_path}")
    assert listed["pendulum_rod"].endswith("modeled")
    # 3. green check, 4. in the report
    out = tmp_path / "reports"
    assert cli.main(["check", NAME, "--examples", "10", "--out", str(out)]) == 0
    assert cli.main(["report", NAME, "--out", str(out)]) == 0
    assert f'href="systems/{NAME}.html"' in (out / "index.html").read_text()
    page = (out / "systems" / f"{NAME}.html").read_text()
    assert "Pendulum rod" in page and "conformant" in page and "rho_S" in page and "kg/m^3" in page
    # a model of one's own names its source, not the lecture (the lecture's own systems: "Lecture: ...")
    assert "Source (a model from outside the lecture's catalogue): Example 3.15" in page
    assert "Each equation as its source prints it" in page and "Lecture: " not in page
    assert "Lecture: Example 3.15" in (ROOT / "reports" / "systems" / "pendulum_rod.html").read_text()
    assert (out / "figures" / f"{NAME}.swing.svg").is_file()
    # nothing left in the repository
    assert sorted(p.name for p in (ROOT / "models").iterdir()) == before
