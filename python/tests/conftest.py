"""Shared pytest helpers: dataset lookup (as tests/testing/data.h), the CLI binary, numeric
Jacobians on the tangent space. slamkit is imported before numpy so that it picks the OpenBLAS
kernels (see slamkit/__init__.py)."""
import os
import pathlib

import slamkit  # noqa: F401  (first: before numpy loads libblas)
import numpy as np
import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("SLAMKIT_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


def data_root():
    env = os.environ.get("SLAMKIT_DATA")
    p = pathlib.Path(env) if env else pathlib.Path("../shared/datasets")
    if not p.is_absolute():
        p = SOURCE_DIR / p
    return p.resolve()


def require_data(relative):
    """The dataset file, or skip (fail under CI=true) when it is missing."""
    p = data_root() / relative
    if not p.exists():
        if os.environ.get("CI") == "true":
            pytest.fail(f"dataset missing under CI: {p}")
        pytest.skip(f"SKIPPED: dataset not found: {p} (set SLAMKIT_DATA)")
    return p


def cli_path():
    p = os.environ.get("SLAMKIT_CLI")
    if not p:
        guess = SOURCE_DIR / "build" / "bin" / "slamkit"
        p = str(guess) if guess.exists() else ""
    if not p:
        if os.environ.get("CI") == "true":
            pytest.fail("SLAMKIT_CLI not set under CI")
        pytest.skip("SKIPPED: slamkit CLI not found (set SLAMKIT_CLI)")
    return p


def numeric_jacobian(f, x, plus, dim, h=1e-6):
    """Central differences of f(x ⊞ δ) w.r.t. δ (f returns a vector, minus-able results)."""
    cols = []
    for c in range(dim):
        d = np.zeros(dim)
        d[c] = h
        cols.append((f(plus(x, d)) - f(plus(x, -d))) / (2 * h))
    return np.stack(cols, axis=1)


# ctest sees a file whose tests were all skipped (no datasets) as skipped, not passed: exit
# code 77 (SKIP_RETURN_CODE in python/CMakeLists.txt, as the C++ shell tests do). Exit code 5
# (nothing collected) stays a failure.
_outcomes = {"passed": 0, "failed": 0, "skipped": 0}


def pytest_runtest_logreport(report):
    if report.when == "call" or report.outcome != "passed":
        _outcomes[report.outcome] = _outcomes.get(report.outcome, 0) + 1


def pytest_sessionfinish(session, exitstatus):
    if exitstatus == 0 and _outcomes["skipped"] > 0 and _outcomes["passed"] == 0 and _outcomes["failed"] == 0:
        session.exitstatus = 77
