"""The committed urdf/ folder is what `harness export` writes now."""

from pathlib import Path

import models
from harness.export.files import export_files

URDF_DIR = Path(__file__).resolve().parent.parent / "urdf"


def test_committed_exports_are_current():
    files = export_files(models.catalogue().values())
    stale = [name for name, text in files.items()
             if not (URDF_DIR / name).exists() or (URDF_DIR / name).read_text() != text]
    assert not stale, f"stale exports {stale}: run `harness export` and commit urdf/"
    extra = {p.name for p in URDF_DIR.iterdir()} - set(files)
    assert not extra, f"urdf/ has files no system exports: {sorted(extra)}"
