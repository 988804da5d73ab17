"""The public names of the module libdem, and which of them its type stubs (.pyi) or its docstrings
leave out: shared by the API tests (test_api_docs.py, on the build tree's module) and the pip
package's check (tests/consumer/pip_install_check.py, on the installed package)."""

import ast
import re


def is_enum(cls):
    members = getattr(cls, "__members__", None)
    return isinstance(members, dict) and bool(members) and all(isinstance(v, cls) for v in members.values())


def public_names(module):
    """'Name' for each public attribute of the module and 'Class.member' for each public member a
    class defines itself, with its constructor and __call__ where the bindings define them."""
    names = []
    for name, value in vars(module).items():
        if name.startswith("_"):
            continue
        names.append(name)
        if isinstance(value, type) and not issubclass(value, BaseException):
            for member, attribute in vars(value).items():
                defined = type(attribute).__name__ == "instancemethod"  # not the "no constructor" slot
                if not member.startswith("_") or (member in ("__init__", "__call__") and defined):
                    names.append(f"{name}.{member}")
    return names


def stub_names(text):
    """The names a .pyi defines: module level, and 'Class.member' inside its classes."""
    found = set()

    def visit(body, prefix):
        for node in body:
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                found.add(prefix + node.name)
                if isinstance(node, ast.ClassDef):
                    visit(node.body, prefix + node.name + ".")
            elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
                found.add(prefix + node.target.id)
            elif isinstance(node, ast.Assign):
                found.update(prefix + t.id for t in node.targets if isinstance(t, ast.Name))

    visit(ast.parse(text).body, "")
    return found


def missing_from_stubs(module, stub_text):
    """(public names, those the stubs do not define)."""
    public = public_names(module)
    defined = stub_names(stub_text)
    return public, [name for name in public if name not in defined]


def docstring_bodies(function):
    """The text under each signature of a pybind11 function's docstring, one per overload."""
    lines = (function.__doc__ or "").splitlines()
    if len(lines) > 1 and lines[1].strip() == "Overloaded function.":
        pieces = re.split(r"^\d+\. \w+\(.*$", "\n".join(lines[2:]), flags=re.MULTILINE)
        return [piece.strip() for piece in pieces[1:]]
    return ["\n".join(lines[1:]).strip()]


def undocumented(module):
    """The public names whose docstring says nothing beyond pybind11's signature. Enums' own
    machinery (name, value, the dunders) is pybind11's and documented by Python."""
    missing = []
    for name, value in vars(module).items():
        if name.startswith("_"):
            continue
        if isinstance(value, type):
            if not (value.__doc__ or "").strip():
                missing.append(name)
            if issubclass(value, BaseException):
                continue
            if is_enum(value):
                described = re.findall(r"^\s+(\w+) : \S", value.__doc__ or "", flags=re.MULTILINE)
                missing += [f"{name}.{member}" for member in value.__members__ if member not in described]
                continue
            for member, attribute in vars(value).items():
                if member.startswith("_") and member not in ("__init__", "__call__"):
                    continue
                where = f"{name}.{member}"
                if isinstance(attribute, property):
                    if not (attribute.__doc__ or "").strip() or attribute.__doc__ == attribute.fget.__doc__:
                        missing.append(where)
                elif isinstance(attribute, staticmethod):
                    missing += [where] if not all(docstring_bodies(attribute.__func__)) else []
                elif type(attribute).__name__ == "instancemethod":
                    missing += [where] if not all(docstring_bodies(attribute)) else []
        elif callable(value):
            missing += [name] if not all(docstring_bodies(value)) else []
    return missing
