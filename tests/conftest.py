"""Set-up of the test session: numpy's elementary functions are the C library's, and its dot products plain sums.

On a CPU with AVX-512 numpy computes ``arctan2``, ``arccos``, ``tan``, ``exp``, ``log`` and others with its own
vectorized routines (Intel's SVML), whose last bit differs from the C library's for about 1 % of arguments (as
measured on this project's AMD EPYC machine: 1489 of 20 000 ``arctan2`` values, 1854 ``arccos``, 925 ``exp``). The
compiled kernels (numba) and Python's ``math`` call the C library, on any CPU. The tests that pin a kernel bit for bit
to the numpy formulation it replaced (``test_kernels.py``, ``test_tip_kernels.py``, ``test_merge.py``,
``test_curvature_knots.py``) compare the kernel's arithmetic with numpy's, so they need numpy's elementary functions
to be the C library's, as they are on every CPU without AVX-512. The session therefore turns numpy's AVX-512 dispatch
off before numpy is first imported (``NPY_DISABLE_CPU_FEATURES``: numpy ignores the names that this CPU or this numpy
version does not have; processes the tests start inherit it).

Likewise OpenBLAS's dot product on such a CPU (its ``SkylakeX`` kernels) forms ``a @ b`` of two short vectors with
fused multiply-adds, which round differently from the kernels' ``a0 b0 + a1 b1`` in about a quarter of cases
(4930 of 20 000 pairs of 2-vectors); its ``Haswell`` kernels, which every AVX-512 CPU can run, add plain products as
the formulations' own machines did. The session asks OpenBLAS for those (``OPENBLAS_CORETYPE``) on a CPU with
AVX-512 only. The library itself does not depend on it: its kernels
give the same bits either way, interpreted or compiled (``test_interpreted.py`` checks the interpreted kernels with
numpy's AVX-512 dispatch on, in a process of its own).
"""
import os
import sys

#: numpy's names of the AVX-512 feature groups: numpy >= 2.4 (``X86_V4`` ...) and before it (``AVX512F`` ...).
AVX512_FEATURES = ("X86_V4 AVX512_ICL AVX512_SPR AVX512F AVX512CD AVX512_KNL AVX512_KNM AVX512_SKX AVX512_CLX "
                   "AVX512_CNL")



def _has_avx512():
    try:
        with open("/proc/cpuinfo") as cpuinfo:
            return any(line.startswith("flags") and " avx512f" in line for line in cpuinfo)
    except OSError:  # not Linux: no SkylakeX kernels are forced on it either way
        return False


if "numpy" not in sys.modules:
    os.environ.setdefault("NPY_DISABLE_CPU_FEATURES", AVX512_FEATURES)
    if _has_avx512():
        os.environ.setdefault("OPENBLAS_CORETYPE", "Haswell")
