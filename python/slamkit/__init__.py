"""slamkit: back-end SLAM toolkit — Lie groups, factor graphs, pose-graph optimization and
trajectory evaluation — with NumPy arrays in and out. See docs/python.md.

Everything lives in the compiled extension slamkit._slamkit and is re-exported here.
"""
import os as _os
import warnings as _warnings


def _prefer_fast_openblas_kernels():
    # Debian 12's OpenBLAS does not recognise recent CPUs and then runs its generic SSE3
    # kernels, which make CHOLMOD's supernodal factorization about 2x slower. OpenBLAS reads
    # OPENBLAS_CORETYPE only while it loads, so the CLI re-executes itself with it set
    # (slamkit/linear/blas_runtime.h); a Python module cannot, but it can set it before the
    # extension loads libblas, when nothing has loaded it yet. SLAMKIT_KEEP_BLAS_CORE=1 opts out.
    if _os.environ.get("OPENBLAS_CORETYPE") or _os.environ.get("SLAMKIT_KEEP_BLAS_CORE"):
        return
    try:
        with open("/proc/self/maps") as maps:
            if any("libblas" in line or "libopenblas" in line for line in maps):
                return  # already loaded (e.g. by numpy): too late, see the warning below
        flags = set()
        with open("/proc/cpuinfo") as cpuinfo:
            for line in cpuinfo:
                if line.startswith("flags"):
                    flags = set(line.split(":", 1)[1].split())
                    break
    except OSError:
        return
    if {"avx512f", "avx512bw", "avx512vl", "avx512dq"} <= flags:
        _os.environ["OPENBLAS_CORETYPE"] = "SkylakeX"
    elif {"avx2", "fma"} <= flags:
        _os.environ["OPENBLAS_CORETYPE"] = "Haswell"


_prefer_fast_openblas_kernels()

from ._slamkit import *  # noqa: E402,F401,F403
from ._slamkit import __version__, blas_runtime  # noqa: E402,F401

if blas_runtime()["better_core"]:
    _warnings.warn(
        "OpenBLAS was loaded before slamkit (e.g. by numpy) and runs its generic %s kernels; sparse "
        "factorizations are about 2x slower. Import slamkit before numpy, or set OPENBLAS_CORETYPE=%s."
        % (blas_runtime()["core"], blas_runtime()["better_core"]),
        RuntimeWarning,
        stacklevel=2,
    )
