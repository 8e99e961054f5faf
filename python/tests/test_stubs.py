"""The type stubs (fulcrum/__init__.pyi, shipped next to the package) name
every public class, function, method and property, so editors complete all."""
import ast
import pathlib

import fulcrum

STUB = pathlib.Path(fulcrum.__file__).with_name("__init__.pyi")


def stub_names():
    tree = ast.parse(STUB.read_text())
    classes, functions = {}, set()
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            names = set()
            for item in node.body:
                if isinstance(item, ast.FunctionDef):
                    names.add(item.name)
                elif isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name):
                    names.add(item.target.id)
            classes[node.name] = names
        elif isinstance(node, ast.FunctionDef):
            functions.add(node.name)
    return classes, functions


def test_the_stubs_cover_the_public_api():
    assert STUB.exists(), f"{STUB} is not installed next to the package"
    classes, functions = stub_names()
    for name in fulcrum.__all__:
        obj = getattr(fulcrum, name)
        if isinstance(obj, type):
            if issubclass(obj, Exception):
                assert name in classes, name
                continue
            assert name in classes, f"class {name} missing from the stubs"
            inherited = set().union(*(classes.get(base.__name__, set()) for base in obj.__mro__[1:]))
            public = {m for m in vars(obj) if not m.startswith("_")}
            missing = public - classes[name] - inherited
            assert not missing, f"{name}: {sorted(missing)} missing from the stubs"
        elif callable(obj):
            assert name in functions, f"function {name} missing from the stubs"
