"""Names the argument of a wrong type in a call of plumb's functions.

nanobind refuses an argument of the wrong type with a list of the function's whole signature
(``verify(None)``: 431 characters); plumb wraps each function of the module so that the error
names the argument, the types it takes and the type it was given::

    TypeError: verify(): model expects Model | mujoco.MjModel | str | os.PathLike[str], not None

The check runs only after nanobind has refused the call, so a call that is accepted costs one
Python frame more and nothing else.
"""

import ast
import collections.abc
import functools
import os
import re
from typing import Any, Callable, TypeVar

_F = TypeVar("_F", bound=Callable[..., Any])

# what each name in an annotation accepts; names not here (plumb's own classes, mujoco's)
# are matched by the type's name
_SIMPLE: dict[str, Callable[[Any], bool]] = {
    "None": lambda v: v is None,
    "bool": lambda v: isinstance(v, bool),
    "int": lambda v: isinstance(v, int) and not isinstance(v, bool),
    "float": lambda v: isinstance(v, (int, float)) and not isinstance(v, bool),
    "str": lambda v: isinstance(v, str),
    "Any": lambda v: True,
    "object": lambda v: True,
}


def _accepts(node: ast.expr, value: Any) -> bool:
    """Whether `value` fits the annotation `node` (a union of names, generics, None)."""
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.BitOr):
        return _accepts(node.left, value) or _accepts(node.right, value)
    if isinstance(node, ast.Constant):
        return value is None if node.value is None else True
    if isinstance(node, ast.Subscript):  # Sequence[str], Mapping[str, ...], list[...]
        base = ast.unparse(node.value).rsplit(".", 1)[-1]
        if base in ("Sequence", "list"):
            if isinstance(value, (str, bytes)) or not isinstance(value, (list, tuple)):
                return False
            return all(_accepts(node.slice, item) for item in value)
        if base in ("Mapping", "dict"):
            return isinstance(value, collections.abc.Mapping)
        if base == "PathLike":
            return isinstance(value, os.PathLike)
        return True
    name = ast.unparse(node)
    short = name.rsplit(".", 1)[-1]
    if short in _SIMPLE:
        return _SIMPLE[short](value)
    if short == "PathLike":
        return isinstance(value, os.PathLike)
    return any(t.__name__ == short for t in type(value).__mro__)


def _parameters(function: Any) -> tuple[list[tuple[str, str, ast.expr | None, bool]], int]:
    """(name, annotation text, annotation, required) of each parameter of the first
    signature, and how many of them may be given by position."""
    text = function.__nb_signature__[0][0]
    text = re.sub(r"\\\d+", "None", text)  # default values are placeholders
    tree = ast.parse(text.strip() + ": pass")
    node = tree.body[0]
    assert isinstance(node, ast.FunctionDef)
    out = []
    a = node.args
    positional = [*a.posonlyargs, *a.args]
    first_default = len(positional) - len(a.defaults)
    for k, arg in enumerate(positional):
        out.append((arg.arg, ast.unparse(arg.annotation) if arg.annotation else "",
                    arg.annotation, k < first_default))
    for arg, default in zip(a.kwonlyargs, a.kw_defaults):
        out.append((arg.arg, ast.unparse(arg.annotation) if arg.annotation else "",
                    arg.annotation, default is None))
    return out, len(positional)


def _which(function: Any, args: tuple[Any, ...], kwargs: dict[str, Any]) -> str | None:
    """The message naming the first argument that fits no type of its parameter."""
    name = function.__name__
    try:
        parameters, positional = _parameters(function)
    except (AttributeError, IndexError, SyntaxError, AssertionError):
        return None
    names = [p[0] for p in parameters]
    given = dict(zip(names[:positional], args))
    for key in kwargs:
        if key not in names:
            return f"{name}(): no argument is named {key!r}; it takes {', '.join(names)}"
        if key in given:
            return f"{name}(): {key} is given twice, by position and by keyword"
    given.update(kwargs)
    for parameter, text, annotation, required in parameters:
        if required and parameter not in given:
            return f"{name}(): {parameter} is missing ({text})"
        if parameter in given and annotation is not None:
            value = given[parameter]
            if not _accepts(annotation, value):
                return (f"{name}(): {parameter} expects {text}, not "
                        f"{'None' if value is None else type(value).__name__}")
    return None


def name_wrong_arguments(function: _F) -> _F:
    """`function` (of plumb._plumb), whose refusal of an argument's type names the argument."""

    @functools.wraps(function)
    def call(*args: Any, **kwargs: Any) -> Any:
        try:
            return function(*args, **kwargs)
        except TypeError as error:
            if "incompatible function arguments" not in str(error):
                raise
            message = _which(function, args, kwargs)
            if message is None:
                raise
        raise TypeError(message)

    call.__nb_signature__ = function.__nb_signature__  # type: ignore[attr-defined]
    return call  # type: ignore[return-value]
