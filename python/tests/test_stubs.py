"""The type stubs (python/woven/_woven.pyi) against the built module: every public name of
woven._woven is in the stubs and every name of the stubs is in the module, each of the same kind
(function, class, property, static method) with the same parameters, read from the signatures
pybind11 writes at the head of each docstring. A binding added without its stub fails here."""
import ast
import inspect
import os

import pytest

import woven._woven as ext

STUB = os.path.join(os.path.dirname(__file__), "..", "woven", "_woven.pyi")


def split_top(text):
    """`text` split at the commas outside brackets and quotes."""
    parts, depth, quote, cur = [], 0, None, ""
    for c in text:
        if quote:
            quote = None if c == quote else quote
        elif c in "'\"":
            quote = c
        elif c in "([{<":
            depth += 1
        elif c in ")]}>":
            depth -= 1
        elif c == "," and depth == 0:
            parts.append(cur)
            cur = ""
            continue
        cur += c
    if cur.strip():
        parts.append(cur)
    return [p.strip() for p in parts]


def doc_params(obj, name):
    """The parameters of a pybind11 function from its docstring's signature line: names, '*'
    for the start of the keyword-only ones, '*args' and '**kwargs'; self left out."""
    doc = obj.__doc__ or ""
    line = next((l for l in doc.splitlines() if l.startswith(name + "(")), None)
    assert line is not None, f"{name}: no signature in its docstring"
    depth, end = 0, None
    for k, c in enumerate(line):
        if c == "(":
            depth += 1
        elif c == ")":
            depth -= 1
            if depth == 0:
                end = k
                break
    names = []
    for p in split_top(line[len(name) + 1:end]):
        n = p.split(":")[0].split("=")[0].strip()
        if n != "self":
            names.append(n)
    return names


def stub_params(fn):
    """The same list from a stub's def."""
    a = fn.args
    names = [x.arg for x in a.posonlyargs + a.args]
    if a.vararg:
        names.append("*" + a.vararg.arg)
    elif a.kwonlyargs:
        names.append("*")
    names += [x.arg for x in a.kwonlyargs]
    if a.kwarg:
        names.append("**" + a.kwarg.arg)
    return [n for n in names if n != "self"]


def decorators(fn):
    return {d.id if isinstance(d, ast.Name) else d.attr for d in fn.decorator_list}


def stub_members(node):
    """{name: (kind, params)} of a stub class or module."""
    out = {}
    for item in node.body:
        if isinstance(item, ast.FunctionDef):
            d = decorators(item)
            if "property" in d:
                out[item.name] = ("property", None)
            elif "setter" in d:
                continue
            elif "staticmethod" in d:
                out[item.name] = ("staticmethod", stub_params(item))
            else:
                out[item.name] = ("function", stub_params(item))
        elif isinstance(item, ast.ClassDef):
            out[item.name] = ("class", item)
        elif isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
            out[item.target.id] = ("attribute", None)
    return out


def public(names):
    return {n for n in names if not n.startswith("_")}


STUBS = stub_members(ast.parse(open(STUB).read()))
ALIASES = {"PathLike", "Progress", "FabricLike"}  # the stub's own type aliases


def test_every_public_name_of_the_module_is_in_the_stubs():
    missing = (public(dir(ext)) | {"__version__"}) - set(STUBS)
    assert not missing, f"in woven._woven but not in _woven.pyi: {sorted(missing)}"


def test_every_stub_name_is_in_the_module():
    extra = {n for n in STUBS if not hasattr(ext, n)} - ALIASES
    assert not extra, f"in _woven.pyi but not in woven._woven: {sorted(extra)}"


@pytest.mark.parametrize("name", sorted(n for n, (kind, _) in STUBS.items() if kind == "function"))
def test_function_parameters(name):
    assert doc_params(getattr(ext, name), name) == STUBS[name][1]


@pytest.mark.parametrize("name", sorted(n for n, (kind, _) in STUBS.items() if kind == "class"))
def test_class_members(name):
    cls = getattr(ext, name)
    members = stub_members(STUBS[name][1])
    if issubclass(cls, BaseException) or cls is ext.InputWarning:
        assert not members
        return
    own = public(k for k in vars(cls))
    assert own == public(members), f"{name}: members differ: module {sorted(own)}, stubs {sorted(public(members))}"
    for member, (kind, params) in members.items():
        static = inspect.getattr_static(cls, member)
        if kind == "property":
            assert isinstance(static, property), f"{name}.{member}: not a property"
        elif member == "__init__":
            assert doc_params(cls.__init__, "__init__") == params, f"{name}.__init__"
        else:
            assert (kind == "staticmethod") == isinstance(static, staticmethod), f"{name}.{member}: static or not"
            assert doc_params(getattr(cls, member), member) == params, f"{name}.{member}"


def test_the_check_fails_on_a_binding_without_a_stub():
    # The comparison itself: a name the module would have and the stubs not is reported.
    names = public(dir(ext)) | {"new_binding"}
    assert names - set(STUBS) == {"new_binding"}
