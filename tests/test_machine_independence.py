"""Verdicts that hold on any machine: a sample of the checks nearest to their bounds, rerun in fresh processes
under the perturbations another x86-64 machine would bring — other BLAS kernels (``OPENBLAS_CORETYPE``),
NumPy without its AVX2/FMA paths (``NPY_DISABLE_CPU_FEATURES``), other thread counts, every input moved by a few
ulps. No verdict may flip. (Pinocchio and MuJoCo are compiled without runtime CPU dispatch; the perturbations
reach our symbolic side, the integrators and the input data of every source.)"""

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

WORKER = Path(__file__).with_name("perturbed_checks.py")
# the conformance checks and scenes whose ratios were highest in the main job (see the margin report)
SAMPLE = ["--systems", "rotating_body", "governor", "spherical_pendulum", "--examples", "40",
          "--scenes", "cable_pulley/haul", "stick_slip/stick_slip", "series_rlc/lc_ring"]
PERTURBATIONS = {
    "baseline": ({}, 0),
    "older CPU kernels": ({"OPENBLAS_CORETYPE": "Prescott", "NPY_DISABLE_CPU_FEATURES": "X86_V3"}, 0),
    "two BLAS threads": ({"OPENBLAS_NUM_THREADS": "2", "OMP_NUM_THREADS": "2"}, 0),
    "inputs moved by 3 ulps": ({}, 3),
}


def run(env: dict, ulps: int) -> dict:
    result = subprocess.run([sys.executable, str(WORKER), "--ulps", str(ulps), *SAMPLE], capture_output=True,
                            text=True, timeout=900, env={**os.environ, **env})
    assert result.returncode == 0, result.stderr[-3000:]
    return json.loads(result.stdout)["checks"]


@pytest.fixture(scope="module")
def runs():
    return {name: run(env, ulps) for name, (env, ulps) in PERTURBATIONS.items()}


def test_no_verdict_flips_under_perturbation(runs):
    baseline = runs["baseline"]
    assert len(baseline) > 50 and all(passed for passed, _ in baseline.values()), \
        [k for k, (passed, _) in baseline.items() if not passed]
    for name, checks in runs.items():
        assert checks.keys() == baseline.keys(), (name, sorted(checks.keys() ^ baseline.keys()))
        flipped = {k: (baseline[k], v) for k, v in checks.items() if v[0] != baseline[k][0]}
        assert not flipped, (name, flipped)


def _kernels() -> list[dict]:
    """Environments selecting the OpenBLAS kernels (and NumPy SIMD paths) this CPU can run: forcing a kernel whose
    instructions it lacks would stop the process."""
    flags = set(re.search(r"^flags\s*:(.*)$", Path("/proc/cpuinfo").read_text(), re.M).group(1).split())
    out = [{"OPENBLAS_CORETYPE": "Prescott", "NPY_DISABLE_CPU_FEATURES": "X86_V3"}]   # no FMA, no AVX
    if {"avx2", "fma"} <= flags:
        out += [{"OPENBLAS_CORETYPE": "Haswell"}, {"OPENBLAS_CORETYPE": "Zen"}]
    if {"avx512f", "avx512bw", "avx512vl", "avx512dq", "avx512cd"} <= flags:
        out.append({"OPENBLAS_CORETYPE": "SkylakeX"})
    return out


def test_the_exported_files_are_the_same_on_every_kernel():
    """The committed urdf/ is checked digit for digit (``harness export --check``): what it is made of must not
    depend on the CPU. It did: the Panda's visual boxes (NumPy's ``eigh``) and a lumped inertia (``@``) came out
    with other last digits under OpenBLAS's AVX-512 and SSE3 kernels than under its AVX2 ones."""
    urdf = Path(__file__).resolve().parent.parent / "urdf"
    for env in _kernels():
        proc = subprocess.run([sys.executable, "-m", "harness.cli", "export", "--check", "--dir", str(urdf)],
                              capture_output=True, text=True, timeout=300, env={**os.environ, **env})
        assert proc.returncode == 0, (env, proc.stdout[-2000:] + proc.stderr[-2000:])
