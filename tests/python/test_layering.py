"""The Python package is layered: every module imports only modules of lower layers (or of its
own layer, without a cycle), at module level and inside functions alike, and only the low-level
layer (with `_native`, `_errors` and `_arrays`) touches the C library. The imports are read
from the sources with `ast`, so an import hidden in a function body counts as much as one at
the top. The layers are drawn in docs/architecture.md."""
import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "python" / "fputlab"

#: the layers, lowest first; a module of a subpackage belongs to the subpackage's layer unless
#: it is listed itself (the longest dotted prefix decides: io.atomic and io.store, the file
#: primitives every layer writes through, sit at the bottom while io's drivers sit above)
LAYERS = [
    ("private helpers", {"_native", "_errors", "_arrays", "_validate", "_display", "_figure",
                         "_engine", "io.atomic", "io.store"}),
    ("low level", {"_lowlevel", "_pacing", "engine"}),
    ("model", {"lattice", "modes", "initial_states"}),
    ("integrate", {"integrate"}),
    ("analysis", {"analysis", "chaos", "chaos_batch", "blowup", "reduction", "thermalization",
                  "recurrence", "sampled"}),
    ("files and ensembles", {"io", "ensemble", "study", "thermalization_study"}),
    ("plots and figures", {"plotting", "figures", "figures_reduction", "figures_open", "demo",
                           "figures_thermalization"}),
    ("interface", {"cli", "__main__", ""}),       # "": the package itself (fputlab/__init__.py)
]
#: modules allowed to import the cffi extension (`lib`, `ffi`)
C_BRIDGE = {"_native", "_errors", "_arrays", "_lowlevel"}


def modules() -> dict[str, Path]:
    """Dotted names relative to the package ("" for the package, "reduction.envelope", ...)."""
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = list(path.relative_to(PACKAGE).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def layer_of(name: str) -> int:
    parts = name.split(".")
    for n in range(len(parts), 0, -1):
        prefix = ".".join(parts[:n])
        for i, (_, members) in enumerate(LAYERS):
            if prefix in members:
                return i
    raise AssertionError(f"fputlab.{name} is in no layer: add it to LAYERS in {__file__} and to "
                         "the table in docs/architecture.md")


def resolve(importer: str, is_package: bool, node, known: set[str]) -> list[tuple[str, int]]:
    """The package modules an import statement loads, with its line number."""
    found = []
    if isinstance(node, ast.Import):
        for alias in node.names:
            if alias.name == "fputlab" or alias.name.startswith("fputlab."):
                found.append(alias.name[len("fputlab."):] if alias.name != "fputlab" else "")
    elif isinstance(node, ast.ImportFrom):
        if node.level == 0:
            if node.module != "fputlab" and not (node.module or "").startswith("fputlab."):
                return []
            base = node.module[len("fputlab."):] if node.module != "fputlab" else ""
        else:
            here = importer.split(".") if importer else []
            if not is_package:
                here = here[:-1]
            here = here[:len(here) - (node.level - 1)]
            base = ".".join(here + ([node.module] if node.module else []))
        for alias in node.names:
            sub = f"{base}.{alias.name}" if base else alias.name
            found.append(sub if sub in known else base)
    return [(name, node.lineno) for name in found]


def imports() -> list[tuple[str, str, int]]:
    """(importer, imported, line) for every import of a package module, anywhere in a file."""
    mods = modules()
    known = set(mods)
    edges = []
    for name, path in mods.items():
        tree = ast.parse(path.read_text(), str(path))
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                for target, line in resolve(name, path.name == "__init__.py", node, known):
                    if target != name:
                        edges.append((name, target, line))
    return edges


def label(name: str) -> str:
    return f"fputlab.{name}" if name else "fputlab"


def test_every_module_has_a_layer():
    for name in modules():
        layer_of(name)


def test_imports_go_downwards_only():
    upward = []
    for importer, target, line in imports():
        if target not in modules():
            continue
        if layer_of(target) > layer_of(importer):
            upward.append(f"{label(importer)} (layer {LAYERS[layer_of(importer)][0]!r}) imports "
                          f"{label(target)} (layer {LAYERS[layer_of(target)][0]!r}) at line {line}")
    assert upward == []


def test_no_import_cycles():
    graph: dict[str, set[str]] = {}
    where = {}
    for importer, target, line in imports():
        # a module of a subpackage always runs its package's __init__ first: not a cycle
        if importer.startswith(target + ".") or target == "":
            continue
        graph.setdefault(importer, set()).add(target)
        where[importer, target] = line
    cycles, state = [], {}

    def visit(node, stack):
        state[node] = "open"
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == "open":
                cyc = stack[stack.index(nxt):] + [nxt]
                cycles.append(" -> ".join(f"{label(a)} (line {where[a, b]})"
                                          for a, b in zip(cyc, cyc[1:])) + f" -> {label(nxt)}")
            elif nxt not in state:
                visit(nxt, stack + [nxt])
        state[node] = "done"

    for node in sorted(graph):
        if node not in state:
            visit(node, [node])
    assert cycles == []


def test_only_the_low_level_layer_touches_the_c_library():
    offenders = [f"{label(a)} imports fputlab._native at line {line}"
                 for a, b, line in imports() if b == "_native" and a not in C_BRIDGE]
    assert offenders == []


@pytest.mark.parametrize("source, expected", [
    ("from .integrate import integrate", "fputlab.lattice imports fputlab.integrate"),
    ("def f():\n    from . import cli", "fputlab.lattice imports fputlab.cli"),
])
def test_the_check_sees_module_and_function_level_imports(source, expected):
    tree = ast.parse(source)
    known = set(modules())
    found = [resolve("lattice", False, node, known) for node in ast.walk(tree)
             if isinstance(node, (ast.Import, ast.ImportFrom))]
    (target, _), = [t for f in found for t in f]
    assert f"fputlab.lattice imports {label(target)}" == expected
    assert layer_of(target) > layer_of("lattice")
