"""The library's BLAS threads (frictionjoint.threads): one thread inside its solvers by default,
the user's settings restored outside them, an override by function or environment variable."""
import numpy as np
import pytest
from threadpoolctl import threadpool_info, threadpool_limits

import frictionjoint as fj
from frictionjoint.errors import ParameterError
from frictionjoint.threads import library_threads


def blas_threads_now() -> set:
    return {lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"}


def test_solvers_run_on_one_blas_thread_and_restore_the_users():
    """Inside library_threads (what every public solver runs in: owns_blas_threads) BLAS has one
    thread, nested blocks too; after it, and after a solver's call, the user's two are back."""
    seen = []
    st = fj.LinearStructure(np.eye(2), [[2.0, -1.0], [-1.0, 1.0]], 0.02 * np.eye(2))
    sysm = fj.FrictionSystem(st, [fj.Jenkins(1.0, 0.1, dof=1)], omega=0.8, excitation=[fj.HarmonicForce(1, 0.5)])
    with threadpool_limits(2, user_api="blas"):
        if blas_threads_now() != {2}:
            pytest.skip("BLAS here cannot take 2 threads")
        with library_threads():
            seen.append(blas_threads_now())
            with library_threads():  # nested: unchanged
                seen.append(blas_threads_now())
        seen.append(blas_threads_now())
        res = fj.periodic_response(sysm)
        seen.append(blas_threads_now())
    assert res.converged
    assert seen == [{1}, {1}, {2}, {2}]
    assert fj.periodic_response.__wrapped__.__name__ == "periodic_response"  # numpydoc and signature kept


def test_the_choice_can_be_overridden():
    try:
        fj.set_blas_threads(None)
        assert fj.blas_threads() is None
        with threadpool_limits(2, user_api="blas"):
            before = blas_threads_now()
            with library_threads():
                assert blas_threads_now() == before  # left as it is
        fj.set_blas_threads(3)
        assert fj.blas_threads() == 3
        for bad in (0, -1, 2.5, True):
            with pytest.raises(ParameterError, match="n must be None or an integer >= 1"):
                fj.set_blas_threads(bad)
    finally:
        import frictionjoint.threads as threads
        threads._choice = threads._UNSET
    assert fj.blas_threads() == 1


@pytest.mark.parametrize("value, expected", [("4", "4"), ("default", "None"), ("0", "ParameterError")])
def test_environment_variable(value, expected, monkeypatch):
    """The variable is read where no choice was made by function (blas_threads reads it at each call, not
    at import): in this process, with the variable set and the choice unset (a subprocess per value took
    2.5 s on a loaded machine, for the import)."""
    import frictionjoint.threads as threads

    monkeypatch.setattr(threads, "_choice", threads._UNSET)
    monkeypatch.setenv("FRICTIONJOINT_BLAS_THREADS", value)
    try:
        got = str(fj.blas_threads())
    except fj.ParameterError:
        got = "ParameterError"
    assert got == expected
