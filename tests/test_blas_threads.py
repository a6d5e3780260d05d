"""One BLAS thread for the fits (``capture.fitting._threads``): set once by the outermost ``one_blas_thread`` of a
thread (trace sets it once around all its fits) and restored when that one is left."""
from __future__ import annotations

import numpy as np
import pytest
from threadpoolctl import ThreadpoolController, threadpool_info

import splinecraft as sc
from splinecraft.capture.fitting import _threads
from splinecraft.capture.fitting._threads import one_blas_thread


def _blas_threads():
    return [entry["num_threads"] for entry in threadpool_info() if entry["user_api"] == "blas"]


@pytest.fixture
def limits_set(monkeypatch):
    """How many times the BLAS limit is set (the controller's ``limit``)."""
    calls = []
    original = ThreadpoolController.limit

    def counted(self, *args, **kwargs):
        calls.append(kwargs)
        return original(self, *args, **kwargs)
    monkeypatch.setattr(ThreadpoolController, "limit", counted)
    monkeypatch.setattr(_threads, "_CONTROLLER", [])
    return calls


def test_nested_limits_set_once_and_restore_at_the_outermost(limits_set):
    before = _blas_threads()
    with one_blas_thread():
        assert all(count == 1 for count in _blas_threads())
        with one_blas_thread():
            assert all(count == 1 for count in _blas_threads())
        assert all(count == 1 for count in _blas_threads())
    assert _blas_threads() == before
    assert len(limits_set) == 1


def test_a_failure_inside_restores_the_limit(limits_set):
    before = _blas_threads()
    with pytest.raises(RuntimeError):
        with one_blas_thread():
            with one_blas_thread():
                raise RuntimeError("inside")
    assert _blas_threads() == before
    with one_blas_thread():  # held no more: set again
        pass
    assert len(limits_set) == 2


def test_trace_sets_the_limit_once_for_all_its_fits(limits_set):
    mask = np.zeros((60, 90), bool)
    for left in (5, 35, 65):  # three outlines of their own, each fitted by lsq
        mask[10:50, left:left + 20] = True
        mask[20:40, left + 7:left + 13] = False
    result = sc.trace(mask)
    assert len(result.fits) == 6
    assert len(limits_set) == 1
