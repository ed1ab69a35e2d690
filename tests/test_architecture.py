"""The package's folders are its layers: imports only go downward, and never in a loop."""

import ast
from pathlib import Path

PKG = Path(__file__).resolve().parents[1] / "src" / "contactalpha"

# Rank of each top-level folder or module: a module may import only from its own rank or lower.
RANKS = {
    "version": 0,
    "defaults": 0,  # what --help shows (a leaf: the CLI builds its parser without a kernel)
    "validation": 0,
    "io": 0,
    "provenance": 0,
    "progress": 0,
    "plotting": 0,
    "engine": 1,
    "laws": 1,  # the contact-law family: beside the engine, which it wraps for n = 3/2
    "models": 2,
    "export": 2,
    "stepping": 2,  # the engines' discrete step maps (numba kernels): below scene and adapters
    "impulse": 2,  # the impulse engines' step maps (rigid contact with restitution): beside stepping
    "baselines": 3,
    "adapters": 4,  # the engines: below scene and the front door, which iterates the adapters' registry
    "scene": 5,  # the physics of a ball under a load: bounces, the separation threshold, the advice
    "dem": 5,  # DEM users' tools: the LAMMPS species table, other codes' names, the load's effect
    "xla": 5,  # the JAX front door (optional extra): tables, laws and the batched engines' blocks
    "parameters": 6,  # the front door (contact_parameters): above scene; imports the adapters' registry
    "warmup": 7,
    "paper": 8,
    "studies": 8,
    "calibration": 8,  # drop-test calibration: scene-level physics, plus a hint from studies
    "mechanism": 8,  # contacts of the user's model files: the adapters' laws at the contact's m_eff
    "config": 9,
    "cli": 9,
    "__main__": 9,
    "__init__": 9,
}


def _modules():
    for path in sorted(PKG.rglob("*.py")):
        parts = path.relative_to(PKG).with_suffix("").parts
        if parts[-1] == "__init__" and len(parts) > 1:
            parts = parts[:-1]
        yield ".".join(parts), path


MODULES = dict(_modules())


def _resolve(name):
    """The package module that ``contactalpha.<name>`` refers to (the longest known prefix)."""
    parts = name.split(".")
    while parts:
        candidate = ".".join(parts)
        if candidate in MODULES:
            return candidate
        parts.pop()
    return None


def _imports(module, path):
    """(imported module, imported names) for every import of a package module."""
    tree = ast.parse(path.read_text())
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".") if package else []
                base = base[: len(base) - (node.level - 1)]
                full = ".".join([*base, *([node.module] if node.module else [])])
            elif node.module and node.module.startswith("contactalpha"):
                full = node.module[len("contactalpha") :].lstrip(".")
            else:
                continue
            for alias in node.names:
                sub = f"{full}.{alias.name}" if full else alias.name
                target = sub if sub in MODULES else _resolve(full) if full else None
                yield target, alias.name
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.startswith("contactalpha."):
                    yield _resolve(alias.name[len("contactalpha.") :]), None


def _rank(module):
    return RANKS[module.split(".")[0] if module else "__init__"]


def test_every_module_has_a_layer():
    unknown = sorted({m.split(".")[0] for m in MODULES if m and m.split(".")[0] not in RANKS})
    assert unknown == []


def test_imports_only_go_down():
    upward = []
    for module, path in MODULES.items():
        for target, _ in _imports(module, path):
            if target is not None and target != "" and _rank(target) > _rank(module):
                upward.append(f"{module} -> {target}")
    assert upward == []


def test_the_front_door_and_adapters_import_one_way():
    """``parameters`` imports ``adapters`` (the front door iterates the engines), never the reverse.

    Neither do ``adapters`` nor ``scene`` (the ball's physics, below the front door) import
    ``parameters``.
    """
    assert _rank("adapters") < _rank("scene") < _rank("parameters")
    below = {"adapters": ("scene", "parameters"), "scene": ("parameters",)}
    back = [
        f"{module} -> {target}"
        for module, path in MODULES.items()
        for target, _ in _imports(module, path)
        if target and target.split(".")[0] in below.get(module.split(".")[0], ())
    ]
    assert back == []


def test_no_private_name_crosses_modules():
    private = []
    for module, path in MODULES.items():
        for target, name in _imports(module, path):
            if name and name.startswith("_") and name != "__version__" and target != module:
                private.append(f"{module} imports {name} from {target}")
    assert private == []


def test_no_import_loop():
    graph = {m: set() for m in MODULES}
    for module, path in MODULES.items():
        for target, _ in _imports(module, path):
            # A package's __init__ re-exporting its own submodules is not a loop.
            if target and target != module and not target.startswith(f"{module}.") and module != "":
                graph[module].add(target)
    index, low, stack, on_stack, loops = {}, {}, [], set(), []

    def visit(v):  # Tarjan's strongly connected components
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                loops.append(sorted(comp))

    for v in graph:
        if v not in index:
            visit(v)
    assert loops == []


def test_the_check_sees_an_upward_import(tmp_path):
    """The walker itself must catch what it exists to catch."""
    fake = tmp_path / "kernel.py"
    fake.write_text("from contactalpha.paper.surface import compute\nfrom ..models.registry import alpha\n")
    targets = [t for t, _ in _imports("engine.kernel", fake)]
    assert targets == ["paper.surface.compute", "models.registry"]
    assert _rank("engine.kernel") < _rank(targets[0])


def test_test_modules_have_unique_names():
    # The test folders have no __init__.py: pytest imports each module by its basename, so two
    # files of one name stop the whole run at collection.
    tests = Path(__file__).resolve().parent
    names = [p.name for p in tests.rglob("test_*.py")]
    assert sorted({n for n in names if names.count(n) > 1}) == []
