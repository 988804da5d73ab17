#!/usr/bin/python3
"""Writes the type stubs of the built module libdem (libdem.pyi) from the module itself.

Every public class, function, property, enum value and constant is written in the order the
bindings define them, with the signatures pybind11 puts at the head of each docstring and the
docstrings themselves, so that an editor and a type checker see the API and its units. The
signatures' C++ spellings become Python types: an Eigen vector or a NumPy array is ArrayLike as an
argument and an NDArray as a result, a path is str or os.PathLike. A name the stubs could not spell
(a C++ type pybind11 does not know) is an error naming the function, so that a binding gets fixed
rather than a stub that lies.

    python3 python/stubgen.py --path build/python --output build/python/libdem.pyi

CMake runs it after building the module (python/CMakeLists.txt); the pip build installs the result
as libdem/__init__.pyi.
"""

import argparse
import ast
import importlib
import inspect
import re
import sys
from pathlib import Path

MODULE = "libdem"
INDENT = "    "

# The dunder methods a class's stub shows when the bindings define them.
DUNDERS = {"__init__", "__call__", "__eq__", "__ne__", "__hash__", "__int__", "__index__", "__repr__", "__str__",
           "__getstate__", "__setstate__", "__len__", "__iter__", "__getitem__", "__contains__", "__lt__", "__le__",
           "__gt__", "__ge__"}


class StubError(Exception):
    pass


def split_top_level(text, separator=","):
    """Splits at separators outside brackets and quotes."""
    parts, depth, quote, start = [], 0, None, 0
    for i, c in enumerate(text):
        if quote:
            if c == quote and text[i - 1] != "\\":
                quote = None
        elif c in "'\"":
            quote = c
        elif c in "([{<":
            depth += 1
        elif c in ")]}>" and not (c == ">" and text[i - 1] == "-"):
            depth -= 1
        elif c == separator and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    parts.append(text[start:])
    return [p.strip() for p in parts if p.strip()]


def matching_paren(text, start):
    """The index of the parenthesis closing the one at `start`, skipping brackets and quotes."""
    depth, quote = 0, None
    for i in range(start, len(text)):
        c = text[i]
        if quote:
            if c == quote and text[i - 1] != "\\":
                quote = None
        elif c in "'\"":
            quote = c
        elif c in "([{":
            depth += 1
        elif c in ")]}":
            depth -= 1
            if depth == 0:
                return i
    raise StubError(f"unbalanced signature: {text!r}")


def strip_annotated(t):
    """Annotated[X, ...] as X (pybind11 2.12 on spells a std::array Annotated[list[int], FixedSize(3)])."""
    while True:
        found = re.search(r"(?<![\w])(?:typing\.)?Annotated\[", t)
        if not found:
            return t
        open_at = found.end() - 1
        depth, close_at = 0, None
        for i in range(open_at, len(t)):
            if t[i] in "[(":
                depth += 1
            elif t[i] in "])":
                depth -= 1
            if depth == 0:
                close_at = i
                break
        if close_at is None:
            raise StubError(f"unbalanced type: {t!r}")
        inner = split_top_level(t[open_at + 1:close_at])[0]
        t = t[:found.start()] + inner + t[close_at + 1:]


class Types:
    """pybind11's spelling of a type (in a signature) as a type a stub can hold."""

    def __init__(self, module):
        self.module = module
        self.imports = set()

    def python(self, spelled, where, argument):
        t = strip_annotated(spelled.strip())
        # Eigen and NumPy arrays: numpy.ndarray[numpy.float64[3, 1]], numpy.ndarray[numpy.int64], numpy.ndarray
        def array(m):
            dtype = m.group(1)
            if argument:
                self.imports.add("import numpy.typing")
                return "numpy.typing.ArrayLike"
            self.imports.update({"import numpy", "import numpy.typing"})
            return f"numpy.typing.NDArray[{dtype}]" if dtype else "numpy.typing.NDArray[typing.Any]"
        t = re.sub(r"numpy\.ndarray(?:\[(numpy\.\w+)(?:\[[^\]]*\])?(?:,[^\]]*)?\])?", array, t)
        if "NDArray[typing.Any]" in t:
            self.imports.add("import typing")
        # std::array<T, N> is T[N] inside a List
        t = re.sub(r"\b(int|float|bool|str)\[\d+\]", r"\1", t)
        if re.search(r"\bos\.PathLike\b", t):
            self.imports.add("import os")
            t = re.sub(r"\bos\.PathLike\b", "typing.Union[str, os.PathLike[str]]" if argument else "os.PathLike[str]", t)
            self.imports.add("import typing")
        t = re.sub(r"\bfunction\b", "typing.Callable[..., typing.Any]", t)
        t = re.sub(r"(?<![.\w])Callable\b(?!\[)", "Callable[..., Any]", t)  # pybind11 2.12 on: a py::function
        # a py::dict or py::list: the docstring says what it holds
        t = re.sub(r"(?<![.\w])dict\b(?!\[)", "typing.Dict[str, typing.Any]", t)
        t = re.sub(r"(?<![.\w])list\b(?!\[)", "typing.List[typing.Any]", t)
        for name in ("List", "Dict", "Tuple", "Optional", "Callable", "Union", "Sequence", "Iterable", "Iterator", "Any"):
            if re.search(r"(?<![.\w])" + name + r"\b", t):
                self.imports.add("import typing")
                t = re.sub(r"(?<![.\w])" + name + r"\b", "typing." + name, t)
        t = re.sub(r"\b" + MODULE + r"\.", "", t)
        if "::" in t or "<" in t or not t:
            raise StubError(f"{where}: pybind11 spells a type {spelled!r} (a C++ type without a binding?)")
        try:
            ast.parse(t, mode="eval")
        except SyntaxError as e:
            raise StubError(f"{where}: the type {spelled!r} became {t!r}, which is not Python") from e
        return t


class Signature:
    """One signature line of a pybind11 docstring: name(arguments) -> result."""

    def __init__(self, line, types, where):
        line = line.strip()
        open_at = line.index("(")
        close_at = matching_paren(line, open_at)
        self.name = line[:open_at].strip()
        rest = line[close_at + 1:].strip()
        self.result = types.python(rest[2:], where, argument=False) if rest.startswith("->") else "None"
        self.arguments = []
        for k, part in enumerate(split_top_level(line[open_at + 1:close_at])):
            if part in ("*args", "**kwargs", "*", "/"):
                self.arguments.append(part)
                continue
            # "name: type = default"; the default's text may hold ':' and '='
            head = split_top_level(part, "=")[0]
            name, _, spelled = head.partition(":")
            name = name.strip()
            has_default = len(split_top_level(part, "=")) > 1
            if k == 0 and name == "self":
                self.arguments.append("self")
                continue
            typed = f"{name}: {types.python(spelled, where, argument=True)}" if spelled.strip() else name
            if not has_default and any(a.endswith(" = ...") for a in self.arguments) and "*" not in self.arguments:
                # pybind11 takes a required argument after optional ones; Python spells it keyword-only
                self.arguments.append("*")
            self.arguments.append(typed + (" = ..." if has_default else ""))

    def render(self, name, decorators=(), kind="method"):
        arguments = list(self.arguments)
        if kind == "method" and (not arguments or arguments[0] != "self"):
            arguments.insert(0, "self")  # pybind11 names the first argument of a lambda arg0
        if kind == "method" and arguments and arguments[0].startswith("arg0"):
            arguments[0] = "self"
        return [*decorators, f"def {name}({', '.join(arguments)}) -> {self.result}:"]


def docstring_lines(text, indent):
    text = inspect.cleandoc(text or "").strip()
    if not text:
        return []
    text = text.replace("\\", "\\\\").replace('"""', '\\"\\"\\"')
    lines = text.splitlines()
    if len(lines) == 1:
        return [indent + f'"""{lines[0]}"""']
    return [indent + '"""' + lines[0]] + [(indent + line) if line else "" for line in lines[1:]] + [indent + '"""']


def overloads(function, name, types, where):
    """[(Signature, doc)] of a pybind11 function, one per overload."""
    doc = function.__doc__ or ""
    lines = doc.splitlines()
    if len(lines) > 1 and lines[1].strip() == "Overloaded function.":
        body = "\n".join(lines[2:])
        pieces = re.split(r"^\d+\. (?=" + re.escape(name) + r"\()", body, flags=re.MULTILINE)
        found = []
        for piece in pieces:
            if not piece.strip():
                continue
            head, _, rest = piece.partition("\n")
            found.append((Signature(head, types, where), rest))
        return found
    # pybind11 heads each docstring with the signature (under another name for some of an enum's
    # methods: __str__ is "name(self: handle) -> str")
    if not lines or not re.match(r"^\w+\(", lines[0]):
        raise StubError(f"{where}: no signature at the head of its docstring: {doc[:80]!r}")
    return [(Signature(lines[0], types, where), "\n".join(lines[1:]))]


def function_stub(function, name, types, where, indent, kind, overrides=False):
    """`overrides`: a base class has the name with another signature (a type checker is told so)."""
    out = []
    found = overloads(function, name, types, where)
    for signature, doc in found:
        decorators = []
        if kind == "static":
            decorators.append("@staticmethod")
        if len(found) > 1:
            types.imports.add("import typing")
            decorators.append("@typing.overload")
        head = signature.render(name, decorators, "method" if kind == "method" else "function")
        body = docstring_lines(doc, indent + INDENT)
        out += [indent + line for line in head[:-1]]
        out.append(indent + head[-1] + ("" if body else " ...") + ("  # type: ignore[override]" if overrides else ""))
        out += body
    return out


def getter_signature(function, types, where):
    """The signature of a property's getter or setter: '(arg0: X) -> T' or 'name(self: handle) -> T'."""
    line = (function.__doc__ or "").split("\n", 1)[0]
    if not re.match(r"^\w*\(", line):
        raise StubError(f"{where}: its getter or setter has no signature: {function.__doc__!r}")
    return Signature("f" + line[line.index("("):], types, where)


def property_stub(prop, name, types, where, indent):
    if prop.fget is None:
        raise StubError(f"{where}: a property without a getter")
    result = getter_signature(prop.fget, types, where).result
    # pybind11 gives a property without a docstring of its own its getter's (the signature)
    body = docstring_lines(prop.__doc__ if prop.__doc__ != prop.fget.__doc__ else "", indent + INDENT)
    out = [indent + "@property", indent + f"def {name}(self) -> {result}:" + ("" if body else " ...")] + body
    if prop.fset is not None:
        arguments = getter_signature(prop.fset, types, where).arguments
        value = arguments[1].split(":", 1)[1].strip() if len(arguments) > 1 and ":" in arguments[1] else result
        out += [indent + f"@{name}.setter", indent + f"def {name}(self, value: {value}) -> None: ..."]
    return out


def is_pybind_function(obj):
    return type(obj).__name__ in ("builtin_function_or_method", "instancemethod")


def is_enum(cls):
    members = getattr(cls, "__members__", None)
    return isinstance(members, dict) and bool(members) and all(isinstance(v, cls) for v in members.values())


def overrides(cls, name):
    return any(name in vars(base) for base in cls.__mro__[1:] if base.__module__ == MODULE)


def class_stub(cls, types, indent=""):
    bases = [b for b in cls.__bases__ if b.__name__ != "pybind11_object" and b is not object]
    names = [b.__name__ if b.__module__ in (MODULE, "builtins") else f"{b.__module__}.{b.__name__}" for b in bases]
    out = [indent + f"class {cls.__name__}" + (f"({', '.join(names)})" if names else "") + ":"]
    inner = indent + INDENT
    out += docstring_lines(cls.__doc__, inner)
    enum = is_enum(cls)
    members = [] if issubclass(cls, BaseException) else list(cls.__dict__.items())
    if enum:  # the values first, then the machinery
        members.sort(key=lambda item: not isinstance(item[1], cls))
    for name, value in members:
        where = f"{MODULE}.{cls.__name__}.{name}"
        if enum and isinstance(value, cls):
            types.imports.add("import typing")
            out.append(inner + f"{name}: typing.ClassVar[{cls.__name__}]  # = {int(value)}")
        elif enum and name == "__members__":
            types.imports.add("import typing")
            out.append(inner + f"__members__: typing.ClassVar[typing.Dict[str, {cls.__name__}]]")
        elif name.startswith("_") and name not in DUNDERS:
            continue
        elif name == "__init__" and type(value).__name__ == "wrapper_descriptor":
            continue  # no constructor from Python: the World or a function makes these
        elif isinstance(value, property):
            out += property_stub(value, name, types, where, inner)
        elif isinstance(value, staticmethod):
            out += function_stub(value.__func__, name, types, where, inner, "static", overrides(cls, name))
        elif is_pybind_function(value):
            out += function_stub(value, name, types, where, inner, "method", overrides(cls, name) and name not in DUNDERS)
        else:
            raise StubError(f"{where}: a {type(value).__name__}, which the stubs do not know how to write")
    if len(out) == 1:
        out[0] += " ..."
    return out


def module_stub(module):
    types = Types(module)
    body = []
    for name, value in vars(module).items():
        if name.startswith("_"):
            continue
        where = f"{MODULE}.{name}"
        if not (isinstance(value, int) and body and body[-1].startswith(name[:3])):
            body.append("")  # a blank line between definitions, none between like constants
        if isinstance(value, type):
            body += class_stub(value, types)
        elif is_pybind_function(value):
            body += function_stub(value, name, types, where, "", "function")
        elif isinstance(value, (bool, int, float, str)):
            body.append(f"{name}: {type(value).__name__}")
            if isinstance(value, int) and not isinstance(value, bool):
                body[-1] += f"  # = {value}"
        else:
            raise StubError(f"{where}: a {type(value).__name__}, which the stubs do not know how to write")
    head = docstring_lines(module.__doc__, "")
    head += ["", "# Written by python/stubgen.py from the built module: edit the bindings (python/*.cpp), not this file."]
    head += sorted(types.imports)
    text = "\n".join(head + body) + "\n"
    ast.parse(text)  # the stubs are Python
    return text


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--path", required=True, help="the folder that holds the built module")
    parser.add_argument("--output", required=True, help="the .pyi file to write")
    args = parser.parse_args()
    folder = Path(args.path).resolve()
    sys.path.insert(0, str(folder))
    module = importlib.import_module(MODULE)
    if Path(module.__file__).resolve().parent != folder:
        sys.exit(f"stubgen: imported {module.__file__}, not the module in {folder}")
    try:
        text = module_stub(module)
    except StubError as e:
        sys.exit(f"stubgen: {e}")
    Path(args.output).write_text(text)


if __name__ == "__main__":
    main()
