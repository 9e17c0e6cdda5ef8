# SPDX-License-Identifier: BSD-3-Clause
"""The kinctl package's imports point downwards only: no import circle
between its modules (counting the imports inside functions too), nothing
imports the CLI's entry point (kinctl.cli), the argument types
(kinctl.argtypes) import nothing of kinctl, and every module imports on its
own."""
import ast
import os
import subprocess
import sys

import pytest

import kinctl

PACKAGE_DIR = os.path.dirname(os.path.abspath(kinctl.__file__))


def module_names(package_dir):
    return sorted(f[:-3] for f in os.listdir(package_dir) if f.endswith(".py"))


def imports_of(path, package, modules):
    """The package's modules that the file at path imports anywhere in its
    code ("__init__" for a name taken from the package itself)."""
    with open(path, encoding="utf-8") as f:
        tree = ast.parse(f.read(), path)
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                parts = a.name.split(".")
                if parts[0] == package and len(parts) > 1:
                    out.add(parts[1])
        elif isinstance(node, ast.ImportFrom):
            parts = (node.module or "").split(".")
            if node.level:
                parts = [package] + [p for p in parts if p]
            if parts[0] != package:
                continue
            if len(parts) > 1:
                out.add(parts[1])
            else:
                out |= {a.name if a.name in modules else "__init__" for a in node.names}
    return out


def import_graph(package_dir, package="kinctl"):
    """{module: the set of the package's modules it imports}."""
    modules = module_names(package_dir)
    return {m: imports_of(os.path.join(package_dir, m + ".py"), package, modules) - {m} for m in modules}


def find_cycle(graph):
    """One import circle as a list [a, b, ..., a], or None."""
    state, stack = {}, []

    def visit(m):
        state[m] = "open"
        stack.append(m)
        for n in sorted(graph.get(m, ())):
            if state.get(n) == "open":
                return stack[stack.index(n):] + [n]
            if n not in state:
                found = visit(n)
                if found:
                    return found
        stack.pop()
        state[m] = "done"
        return None
    for m in sorted(graph):
        if m not in state:
            found = visit(m)
            if found:
                return found
    return None


def test_the_cycle_finder_finds_a_circle(tmp_path):
    """A package whose b imports a inside a function while a imports b: the
    shape of the circle between kinctl.cli and its command modules once."""
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from pkg import b\n")
    (pkg / "b.py").write_text("def f():\n    from pkg.a import x\n    return x\n")
    (pkg / "c.py").write_text("import pkg.b\n")
    graph = import_graph(str(pkg), "pkg")
    assert graph == {"__init__": set(), "a": {"b"}, "b": {"a"}, "c": {"b"}}
    assert find_cycle(graph) == ["a", "b", "a"]
    (pkg / "b.py").write_text("X = 1\n")
    assert find_cycle(import_graph(str(pkg), "pkg")) is None


def test_no_import_circle():
    graph = import_graph(PACKAGE_DIR)
    assert "cli" in graph and "argtypes" in graph and len(graph) > 20
    cycle = find_cycle(graph)
    assert cycle is None, "import circle: " + " -> ".join(cycle)


def test_nothing_imports_the_entry_point():
    graph = import_graph(PACKAGE_DIR)
    assert sorted(m for m, deps in graph.items() if "cli" in deps) == ["__main__"]


def test_argument_types_are_a_leaf():
    assert import_graph(PACKAGE_DIR)["argtypes"] == set()


@pytest.mark.parametrize("module", [m for m in module_names(PACKAGE_DIR) if m != "__main__"])
def test_every_module_imports_alone(module):
    name = "kinctl" if module == "__init__" else f"kinctl.{module}"
    r = subprocess.run([sys.executable, "-c", f"import {name}"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
