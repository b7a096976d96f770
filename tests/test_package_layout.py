"""The house: the package's import graph has no cycles, and OpenCV loads only where needed."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.cpu_only

PACKAGE_ROOT = Path(__file__).resolve().parents[1] / "host" / "obstacle_fusion"


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE_ROOT.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _modules() -> dict[str, Path]:
    return {_module_name(p): p for p in sorted(PACKAGE_ROOT.rglob("*.py"))}


def import_graph(modules: dict[str, Path]) -> dict[str, set[str]]:
    """Module -> the package modules it imports, at top level or inside functions."""
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        is_package = path.name == "__init__.py"
        edges: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            targets: list[str] = []
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    anchor = name.split(".")
                    anchor = anchor if is_package else anchor[:-1]
                    anchor = anchor[: len(anchor) - (node.level - 1)]
                    base = ".".join([*anchor, base] if base else anchor)
                targets = [base]
                # ``from pkg import submodule`` imports the submodule
                targets += [f"{base}.{alias.name}" for alias in node.names]
            edges.update(t for t in targets if t in modules and t != name)
        graph[name] = edges
    return graph


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One import cycle as a path that starts and ends at the same module, or None."""
    state: dict[str, int] = {}  # 1: on the current path, 2: done
    stack: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                return stack[stack.index(nxt) :] + [nxt]
            if nxt not in state and (cycle := visit(nxt)) is not None:
                return cycle
        stack.pop()
        state[node] = 2
        return None

    for start in sorted(graph):
        if start not in state and (cycle := visit(start)) is not None:
            return cycle
    return None


def test_cycle_finder_sees_a_cycle_through_a_lazy_import() -> None:
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert find_cycle(graph) == ["a", "b", "c", "a"]
    assert find_cycle({"a": {"b"}, "b": set()}) is None


def test_import_graph_reads_relative_and_from_imports(tmp_path: Path) -> None:
    modules = _modules()
    graph = import_graph(modules)
    # the registry imports the methods, never the other way round
    assert "obstacle_fusion.vision.fused" in graph["obstacle_fusion.vision.measure"]
    assert "obstacle_fusion.vision.paper" in graph["obstacle_fusion.vision.measure"]
    assert "obstacle_fusion.vision.types" in graph["obstacle_fusion.vision.paper"]


def test_no_module_imports_a_module_that_imports_it_back() -> None:
    cycle = find_cycle(import_graph(_modules()))
    assert cycle is None, "import cycle: " + " -> ".join(cycle or [])


# Every package, and the modules on the robot's path that have no image work, must import
# without OpenCV (a sonar-only robot or a tool reading logs should not pay for it).
OPENCV_FREE = [
    "obstacle_fusion",
    "obstacle_fusion.cli",
    "obstacle_fusion.errors",
    "obstacle_fusion.bundled",
    "obstacle_fusion.api",
    "obstacle_fusion.app",
    "obstacle_fusion.protocol",
    "obstacle_fusion.protocol.stream",
    "obstacle_fusion.protocol.jsonview",
    "obstacle_fusion.link",
    "obstacle_fusion.link.connection",
    "obstacle_fusion.link.ports",
    "obstacle_fusion.timing",
    "obstacle_fusion.timing.clock",
    "obstacle_fusion.sonar",
    "obstacle_fusion.sources",
    "obstacle_fusion.sources.frames",
    "obstacle_fusion.fusion",
    "obstacle_fusion.outputs",
    "obstacle_fusion.outputs.jsonl",
    "obstacle_fusion.outputs.console",
    "obstacle_fusion.vision",
    "obstacle_fusion.vision.rig",
    "obstacle_fusion.sim",
    "obstacle_fusion.sim.emulator",
    "obstacle_fusion.sim.scenario",
    "obstacle_fusion.sim.emulated_robot",
]


# Packages whose every module works on images: importing them loads OpenCV, by need.
NEEDS_OPENCV = [
    "obstacle_fusion.vision.fused",  # the fused method's stages (gradients, integrals)
]


def test_every_package_is_listed_as_opencv_free_or_needing_it() -> None:
    packages = {n for n, p in _modules().items() if p.name == "__init__.py"}
    listed = set(OPENCV_FREE) | set(NEEDS_OPENCV)
    assert packages <= listed, sorted(packages - listed)
    assert not set(OPENCV_FREE) & set(NEEDS_OPENCV)


@pytest.mark.parametrize("module", OPENCV_FREE)
def test_imports_without_opencv(module: str) -> None:
    probe = f"import sys, {module}; sys.exit(3 if 'cv2' in sys.modules else 0)"
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    assert done.returncode != 3, f"importing {module} loads OpenCV"
    assert done.returncode == 0, done.stderr


def test_the_sensor_class_is_a_lazy_attribute_of_the_package() -> None:
    """`obstacle_fusion.ObstacleSensor` works, and importing the package does not load the
    API (nor the app, the link or OpenCV) until it is used."""
    probe = (
        "import sys, obstacle_fusion\n"
        "assert 'obstacle_fusion.api' not in sys.modules, 'api loaded at import'\n"
        "assert 'obstacle_fusion.app' not in sys.modules, 'app loaded at import'\n"
        "cls = obstacle_fusion.ObstacleSensor\n"
        "assert cls.__module__ == 'obstacle_fusion.api'\n"
        "assert obstacle_fusion.AsyncObstacleSensor.__module__ == 'obstacle_fusion.api'\n"
        "sys.exit(3 if 'cv2' in sys.modules else 0)\n"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    import obstacle_fusion

    with pytest.raises(AttributeError, match="no attribute 'Nope'"):
        obstacle_fusion.Nope  # noqa: B018


@pytest.mark.parametrize("module", ["obstacle_fusion.vision.measure", *NEEDS_OPENCV])
def test_an_opencv_user_is_seen_loading_it(module: str) -> None:
    """The probe itself works: a module that needs OpenCV is reported as loading it."""
    probe = f"import sys, {module}; sys.exit(3 if 'cv2' in sys.modules else 0)"
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    assert done.returncode == 3, done.stderr
