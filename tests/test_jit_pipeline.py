"""The kernels' compiler pipeline (``capture._jit._KernelCompiler``): numba's nopython pipeline without the passes
the kernels do not need, with the typing of builtin calls remembered per argument types while a kernel
compiles (``capture._jit._call_type``); numba's own typing is untouched outside those compiles."""
import operator

import numba
import numpy as np
import pytest
from numba.core import types
from numba.core.types.functions import BaseFunction

from splinecraft.capture import _jit

_OPTIONS = dict(_jit.JIT_OPTIONS, cache=False)  # a fresh compile in every test


def _counting(monkeypatch):
    """The calls numba's own ``get_call_type`` answers while the kernels of a test compile, by function."""
    plain, calls = _jit._PLAIN_CALL_TYPE, {}

    def counted(function, context, args, kws):
        calls[function.typing_key] = calls.get(function.typing_key, 0) + 1
        return plain(function, context, args, kws)
    monkeypatch.setattr(_jit, "_PLAIN_CALL_TYPE", counted)
    monkeypatch.setattr(_jit, "_CALL_TYPES", {})
    return calls


def test_a_kernel_types_each_builtin_call_once_per_argument_types(monkeypatch):
    calls = _counting(monkeypatch)

    @numba.njit(**_OPTIONS)
    def weighted(values, weights, out):
        total = 0.0
        for i in range(values.shape[0]):
            out[i] = values[i] * weights[i] * 2.0 * values[i] * weights[i]
            total += out[i] * out[i]
        return total

    values, weights = np.linspace(0.5, 2.0, 7), np.linspace(3.0, -1.0, 7)
    out = np.empty(7)
    assert weighted(values, weights, out) == pytest.approx(np.sum((values * weights * 2.0 * values * weights) ** 2))
    np.testing.assert_array_equal(out, values * weights * 2.0 * values * weights)
    # five multiplications of two floats and six reads of a float array at an integer, at each round of type
    # inference and once more when lowered: one answer each
    assert calls[operator.mul] == 1
    assert calls[operator.getitem] == 1


def test_remembered_call_types_are_numba_s_own():
    @numba.njit(**_OPTIONS)
    def scaled(values, out):
        for i in range(values.shape[0]):
            out[i] = values[i] * 3.0 - i
        return out[0]

    scaled(np.arange(4.0), np.empty(4))
    context = numba.core.registry.cpu_target.typing_context
    assert _jit._CALL_TYPES
    for (function, typing_context, args), (signature, implementation) in list(_jit._CALL_TYPES.items()):
        if typing_context is context:
            assert _jit._PLAIN_CALL_TYPE(function, context, args, {}) == signature
            assert function.get_impl_key(signature) == implementation


def test_numba_s_own_typing_is_back_after_a_kernel_compiles():
    @numba.njit(**_OPTIONS)
    def fails(values):
        return values.no_such_attribute

    with pytest.raises(numba.core.errors.TypingError):
        fails(np.zeros(3))
    assert BaseFunction.get_call_type is _jit._PLAIN_CALL_TYPE

    @numba.njit(**_OPTIONS)
    def adds(a, b):
        return a + b

    assert adds(2, 3) == 5
    assert BaseFunction.get_call_type is _jit._PLAIN_CALL_TYPE

    @numba.njit(cache=False)  # a compile outside the kernels' pipeline: numba's own typing
    def user_code(a, b):
        return a * b

    remembered = dict(_jit._CALL_TYPES)
    assert user_code(2.5, 4.0) == 10.0
    assert _jit._CALL_TYPES == remembered


def test_a_variable_assigned_two_integer_types_keeps_its_values():
    """Without numba's SSA form a variable has one type for all its assignments (their unification): an
    ``int32`` and an ``int64`` make an ``int64`` with the same values."""
    @numba.njit(**_OPTIONS)
    def widest(small, large):
        best = small[0]
        for value in large:
            if value > best:
                best = value
        return best

    small = np.array([-7], dtype=np.int32)
    large = np.array([3, 2 ** 40, -5], dtype=np.int64)
    assert widest(small, large) == 2 ** 40
    assert widest(small, large[:1] * 0 - 9) == -7
    assert widest.nopython_signatures[0].return_type == types.int64


def _legalizations(monkeypatch):
    """The kernels that went through :class:`_jit._LegalizeWithoutDels` while a test compiles."""
    plain, names = _jit._LegalizeWithoutDels.run_pass, []

    def counted(self, state):
        names.append(state.func_id.func_name)
        return plain(self, state)
    monkeypatch.setattr(_jit._LegalizeWithoutDels, "run_pass", counted)
    return names


@pytest.mark.parametrize("lean", [True, False])
def test_a_numba_without_the_lean_pipeline_s_parts_compiles_through_its_own(monkeypatch, lean):
    monkeypatch.setattr(_jit, "_LEAN_PIPELINE", lean)
    names = _legalizations(monkeypatch)

    @numba.njit(**_OPTIONS)
    def halves(values, out):
        for i in range(values.shape[0]):
            out[i] = values[i] / 2.0
        return out.shape[0]

    values = np.array([3.0, -1.0, 0.5])
    out = np.empty(3)
    assert halves(values, out) == 3
    np.testing.assert_array_equal(out, values / 2.0)
    assert names == (["halves"] if lean else [])


def test_a_function_type_without_implementation_keys_is_typed_by_numba_itself(monkeypatch):
    calls = []

    def plain(function, context, args, kws):
        calls.append(args)
        return ("signature of", args)
    monkeypatch.setattr(_jit, "_PLAIN_CALL_TYPE", plain)
    monkeypatch.setattr(_jit, "_CALL_TYPES", {})

    class Function:  # a numba whose function types keep no ``_impl_keys`` dict
        pass
    args = (types.float64, types.float64)
    assert _jit._call_type(Function(), None, args, {}) == ("signature of", args)
    assert _jit._call_type(Function(), None, args, {}) == ("signature of", args)
    assert calls == [args, args]
    assert _jit._CALL_TYPES == {}
