"""The public API is documented and typed (as python-control checks its docstrings by a test):
every callable exported by ``frictionjoint.__all__`` -- functions, classes (their constructor) and
the classes' public methods -- has a type hint on every parameter and, when it takes parameters,
a numpydoc ``Parameters`` section (result classes may document their fields as ``Attributes``)."""
import inspect

import pytest

import frictionjoint as fj


def _public_callables():
    for name in fj.__all__:
        obj = getattr(fj, name)
        if inspect.isclass(obj):
            if issubclass(obj, BaseException):
                continue
            yield name, obj
            for attr, member in vars(obj).items():
                if attr.startswith("_"):
                    continue
                if isinstance(member, (staticmethod, classmethod)):
                    member = member.__func__
                if callable(member):
                    yield f"{name}.{attr}", member
        elif callable(obj):
            yield name, obj


def _parameters(obj):
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        return None
    return [p for p in sig.parameters.values()
            if p.name not in ("self", "cls") and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]


CALLABLES = [(name, obj) for name, obj in _public_callables() if _parameters(obj) is not None]


def test_the_api_is_large_enough_to_mean_something():
    assert len(CALLABLES) > 80


@pytest.mark.parametrize("name,obj", CALLABLES, ids=[n for n, _ in CALLABLES])
def test_public_callable_has_type_hints_and_parameters_section(name, obj):
    params = _parameters(obj)
    untyped = [p.name for p in params if p.annotation is inspect.Parameter.empty]
    assert not untyped, f"{name}: parameters without a type hint: {untyped}"
    if params:
        doc = inspect.getdoc(obj) or ""
        ok = "Parameters\n----------" in doc or (inspect.isclass(obj) and "Attributes\n----------" in doc)
        assert ok, f"{name}: no numpydoc 'Parameters' section for {[p.name for p in params]}"
