"""The package's Numba compilation, with an on-disk cache that cannot go stale.

Numba keys a cached function on its own source file only, so a compiled function that
inlines or calls compiled code from another file (the engine inlines the controller, the
sensors and the generated model) would keep stale machine code after that other file
changes. Here every compiled function of the package is cached in one folder named after a
fingerprint of the source files the compiled code depends on (``compiled_sources``: each
file that defines a compiled function, and every file that the names used in compiled code,
or in the constants they read, come from, followed through imports; with the Numba and
Python versions): an edit to any of them selects a fresh folder on the next import, so the
edit takes effect with no manual step, while an edit to the command line, the studies, the
plots or the docs keeps the cache. The folder is ``$NUMBA_CACHE_DIR`` (else
``$XDG_CACHE_HOME``, else ``~/.cache``)
``/tetherheli-numba/<fingerprint>``; folders of other fingerprints unused for
``STALE_AFTER_DAYS`` are removed. Where no cache folder can be written, functions compile
in memory (never from a stale cache).

Importing this module raises two of LLVM's loop-vectoriser thresholds for the process
(``VECTORIZER_OPTIONS``): a loop over the lanes of a block of runs reads and writes a few dozen
rows of separate arrays, and LLVM vectorises it only after checking at run time that none of
them overlap; its default budget of 8 such checks leaves the lane loops scalar. The options
only let more loops vectorise; they never change the arithmetic of a lane (the lane engine's
test compares lanes bit for bit with single runs).
"""

from __future__ import annotations

import ast
import contextlib
import copy
import gc
import hashlib
import json
import os
import shutil
import sys
import time
from collections.abc import Callable, Iterator
from functools import lru_cache
from pathlib import Path
from typing import Any

import llvmlite.binding as llvm
import numba
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils, event
from numba.extending import intrinsic

__all__ = [
    "PACKAGE_ROOT",
    "borrowed",
    "cache_directory",
    "compiled",
    "compiled_sources",
    "frozen",
    "inline_here",
    "keep_alive",
    "plain",
    "restrict_arguments",
    "source_fingerprint",
]

PACKAGE_ROOT = Path(__file__).resolve().parent
STALE_AFTER_DAYS = 14
_CACHE_PARENT = "tetherheli-numba"

#: LLVM options set at import: the number of run-time alias checks the loop vectoriser may
#: emit (defaults 8 and 128); see the module docstring
VECTORIZER_OPTIONS = (
    "-runtime-memory-check-threshold=1024",
    "-vectorize-memory-check-threshold=1024",
)
for _option in VECTORIZER_OPTIONS:
    llvm.set_option("", _option)


# --- Numba's inliner: one copy of a callee's scope, not one per block ---------------------------
# Numba inlines an ``inline="always"`` callee by deep-copying its IR block by block
# (``inline_closurecall.InlineWorker.inline_ir``'s ``copy_ir``, twice per call site), each
# block's copy with a copy of the callee's whole scope (every variable of the function): a
# callee of b blocks and v variables costs b v variable copies where b + v would do
# (numba/numba#8989; upstream kept the per-block copy). The engine's phases inline callees of
# 50-60 blocks and 500-850 variables (the controller, the actuators, the wind), so these
# copies took about a third of a first ``tetherheli paper``'s Numba-level compilation. Here
# the blocks of one copy share one memo, as the blocks of a freshly built IR share one scope:
# the copied IR is the same IR (the same statements, variables and locations), built once.
class _SharedScopeCopy:
    """``inline_closurecall``'s ``copy`` module as ``copy_ir`` uses it: ``deepcopy`` of the
    blocks of one IR in a row shares one memo (one copy of their scope); everything else is
    the ``copy`` module's."""

    def __init__(self) -> None:
        self._scope: Any = None
        self._memo: dict[int, Any] = {}

    def deepcopy(self, value: Any, memo: Any = None) -> Any:
        """``copy.deepcopy``, sharing the memo between the blocks of one scope copied in turn
        (a block seen before, or another scope, starts a fresh memo)."""
        from numba.core import ir as numba_ir

        if memo is not None or not isinstance(value, numba_ir.Block):
            return copy.deepcopy(value, memo)
        if value.scope is not self._scope or id(value) in self._memo:
            self._scope, self._memo = value.scope, {}
        return copy.deepcopy(value, self._memo)

    def reset(self) -> None:
        """Forget the last copy (its memo holds the originals and their copies)."""
        self._scope, self._memo = None, {}

    def __getattr__(self, name: str) -> Any:
        return getattr(copy, name)


def _share_inlined_scopes() -> bool:
    """Install ``_SharedScopeCopy`` in Numba's inliner where its code is the one described
    above (``copy.deepcopy`` of each block in ``inline_ir``); returns whether it did."""
    from numba.core import inline_closurecall as icc

    worker = getattr(icc, "InlineWorker", None)
    inline_ir = getattr(worker, "inline_ir", None)
    if getattr(icc, "copy", None) is not copy or inline_ir is None:
        return False
    names = inline_ir.__code__.co_consts
    body = [c for c in names if isinstance(c, type(inline_ir.__code__))]
    if not any("deepcopy" in c.co_names and "blocks" in c.co_names for c in body):
        return False
    shared = _SharedScopeCopy()

    def inline_ir_shared(self: Any, *args: Any, **kwargs: Any) -> Any:
        shared.reset()
        try:
            return inline_ir(self, *args, **kwargs)
        finally:
            shared.reset()

    icc.copy = shared  # type: ignore[assignment]  # the module's one use: copy_ir's deepcopy
    worker.inline_ir = inline_ir_shared  # type: ignore[union-attr]
    return True


SHARED_INLINED_SCOPES = _share_inlined_scopes()

# --- the cyclic garbage collector while Numba compiles -----------------------------------------
#: the collector's thresholds (``gc.set_threshold``) while a compilation runs: Numba's typing
#: and lowering allocate millions of small objects (IR nodes, types, LLVM values), which at
#: Python's default (700, 10, 10) start a collection every 700 allocations and a full one
#: every 70,000, each scanning the growing IR; about a tenth of a first ``tetherheli paper``'s
#: CPU time. Raised for the compilation only (``_CompilationCollector``), restored after it.
COMPILE_GC_THRESHOLDS = (50_000, 20, 20)


class _CompilationCollector(event.Listener):
    """A listener on Numba's ``numba:compile`` events (broadcast under the compiler lock,
    nested for callees): ``COMPILE_GC_THRESHOLDS`` from the outermost start to its end."""

    def __init__(self) -> None:
        self.depth = 0
        self.saved = gc.get_threshold()

    def on_start(self, ev: event.Event) -> None:
        """Raise the thresholds at the outermost compilation's start."""
        if self.depth == 0:
            self.saved = gc.get_threshold()
            gc.set_threshold(*COMPILE_GC_THRESHOLDS)
        self.depth += 1

    def on_end(self, ev: event.Event) -> None:
        """Restore them at its end (also when it fails)."""
        self.depth -= 1
        if self.depth == 0:
            gc.set_threshold(*self.saved)


event.register("numba:compile", _CompilationCollector())


def source_fingerprint(root: Path = PACKAGE_ROOT) -> str:
    """sha256 (16 hex digits) of the ``*.py`` below ``root`` that compiled code depends on
    (``compiled_sources``; paths and contents), with the Numba and Python versions, the LLVM
    options and a ``TETHERHELI_LANES`` override."""
    lanes = os.environ.get("TETHERHELI_LANES", "")  # ``layout.LANES``: a compiled constant
    digest = hashlib.sha256(
        f"{numba.__version__} {sys.version} {VECTORIZER_OPTIONS} {lanes}".encode()
    )
    for path in compiled_sources(root):
        digest.update(path.relative_to(root).as_posix().encode() + b"\0")
        digest.update(path.read_bytes() + b"\0")
    return digest.hexdigest()[:16]


#: the decorator factory whose products mark a function as compiled (``compiled``, Numba's)
_DECORATORS = frozenset({"compiled", "njit", "jit"})


def compiled_sources(root: Path = PACKAGE_ROOT) -> list[Path]:
    """The source files below ``root`` whose edit can change compiled machine code, sorted.

    A walk over the syntax trees (``ast``), conservative where it cannot tell: it starts at
    every function that a module compiles (decorated by ``compiled``/``njit`` or a name bound
    to one, or passed to such a name, e.g. ``kernels.free_rhs = _jit(gen.free_rhs)``) and
    follows each name such a function uses to where it is defined: a function or class (its
    whole body followed), a module-level assignment (its value followed), an import from a
    module below ``root`` (that module's file, and the name there), a module (the attribute
    used). ``_compile.py`` itself is always included (the options); a file that cannot be
    parsed, or a star import, falls back to every file.

    Parameters
    ----------
    root : Path
        The package folder.

    Returns
    -------
    list of Path
    """
    root = Path(root)
    every = sorted(root.rglob("*.py"))
    # the walk parses a dozen files (about 0.5 s): its answer is kept beside the caches,
    # keyed on every file's path, size and modification time
    stamps = hashlib.sha256(str(root.resolve()).encode())
    for path in every:
        st = path.stat()
        stamps.update(f"{path.relative_to(root).as_posix()} {st.st_size} {st.st_mtime_ns}\n"
                      .encode())  # fmt: skip
    record = _cache_base() / f"sources-{stamps.hexdigest()[:16]}.json"
    with contextlib.suppress(OSError, ValueError):
        return [root / rel for rel in json.loads(record.read_text(encoding="utf-8"))]
    try:
        files = _DependencyWalk(root).files()
    except _Unsure:
        files = every
    with contextlib.suppress(OSError):
        record.parent.mkdir(parents=True, exist_ok=True)
        tmp = record.with_name(f".{record.name}.{os.getpid()}.tmp")
        tmp.write_text(json.dumps([f.relative_to(root).as_posix() for f in files]))
        os.replace(tmp, record)
    return files


class _Unsure(Exception):
    """The walk cannot tell a dependency: fall back to every file."""


class _Module:
    """The top-level bindings of one source file."""

    def __init__(self, path: Path, name: str, package: str) -> None:
        self.path = path
        self.tree = ast.parse(path.read_bytes(), filename=str(path))
        self.defs: dict[str, list[ast.AST]] = {}  # name -> definitions and assignments
        self.imports: dict[str, tuple[str, str | None]] = {}  # name -> (module, attribute)
        self.factories: set[str] = set(_DECORATORS)  # names bound to compiled(...)
        for node in self.tree.body:
            self._bind(node, name, package)

    def _bind(self, node: ast.AST, name: str, package: str) -> None:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            self.defs.setdefault(node.name, []).append(node)
        elif isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for t in targets:
                for n in ast.walk(t):
                    if isinstance(n, ast.Name):
                        self.defs.setdefault(n.id, []).append(node)
            value = node.value
            if isinstance(value, ast.Call) and _called_name(value.func) in _DECORATORS:
                for t in targets:
                    if isinstance(t, ast.Name):
                        self.factories.add(t.id)
        elif isinstance(node, ast.ImportFrom):
            base = _absolute(node, name, package)
            for a in node.names:
                if a.name == "*":
                    raise _Unsure
                self.imports[a.asname or a.name] = (base, a.name)
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.asname:
                    self.imports[a.asname] = (a.name, None)
                else:
                    self.imports[a.name.partition(".")[0]] = (a.name.partition(".")[0], None)
        elif isinstance(node, (ast.If, ast.Try, ast.With)):
            for child in ast.iter_child_nodes(node):
                if isinstance(child, ast.stmt):
                    self._bind(child, name, package)

    def compiled_roots(self) -> list[ast.AST]:
        """The compiled functions' definitions and the calls that compile a function."""
        roots: list[ast.AST] = []
        for node in ast.walk(self.tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                if any(_called_name(d) in self.factories for d in node.decorator_list):
                    roots.append(node)
            elif isinstance(node, ast.Call) and _called_name(node.func) in self.factories:
                roots.extend(node.args)  # _jit(gen.free_rhs), compiled(...)(function)
                if isinstance(node.func, ast.Call):
                    roots.extend(node.func.args)
        return roots


def _called_name(node: ast.AST) -> str | None:
    """The name a decorator or call refers to: ``f``, ``m.f``, ``f(...)`` -> ``f``."""
    if isinstance(node, ast.Call):
        return _called_name(node.func)
    if isinstance(node, ast.Attribute):
        return node.attr
    if isinstance(node, ast.Name):
        return node.id
    return None


def _absolute(node: ast.ImportFrom, name: str, package: str) -> str:
    if not node.level:
        return node.module or ""
    parts = package.split(".")
    base = parts[: len(parts) - node.level + 1]
    return ".".join(base + ([node.module] if node.module else []))


class _DependencyWalk:
    def __init__(self, root: Path) -> None:
        self.root = root
        self.top = root.name
        self.modules: dict[str, _Module | None] = {}
        self.seen: set[tuple[str, str | None]] = set()
        self.needed: set[Path] = {root / "_compile.py"}

    def module(self, name: str) -> _Module | None:
        """The module ``name`` if it lies below the root (parsed once), else None."""
        if name in self.modules:
            return self.modules[name]
        found = None
        if name == self.top or name.startswith(self.top + "."):
            rel = Path(*name.split(".")[1:])
            package_init = self.root / rel / "__init__.py"
            module_file = (self.root / rel).with_suffix(".py") if rel.parts else None
            try:
                if package_init.is_file():
                    found = _Module(package_init, name, name)
                elif module_file is not None and module_file.is_file():
                    found = _Module(module_file, name, name.rpartition(".")[0])
            except SyntaxError:
                raise _Unsure from None
        self.modules[name] = found
        return found

    def files(self) -> list[Path]:
        for path in sorted(self.root.rglob("*.py")):
            rel = path.relative_to(self.root).with_suffix("")
            parts = [self.top, *rel.parts]
            if parts[-1] == "__init__":
                parts.pop()
            name = ".".join(parts)
            text = path.read_text(encoding="utf-8", errors="replace")
            if not any(d in text for d in _DECORATORS):
                continue
            m = self.module(name)
            if m is None:
                continue
            roots = m.compiled_roots()
            if roots:
                self.needed.add(m.path)
                for node in roots:
                    self.follow_node(name, m, node)
        return sorted(self.needed)

    def follow_node(self, name: str, m: _Module, node: ast.AST) -> None:
        """Follow every name that ``node`` (a definition, an expression) uses in module m."""
        for n in ast.walk(node):
            if isinstance(n, ast.Attribute):
                chain = []
                base: ast.AST = n
                while isinstance(base, ast.Attribute):
                    chain.append(base.attr)
                    base = base.value
                if isinstance(base, ast.Name):
                    self.follow_attribute(name, m, base.id, chain[::-1])
            elif isinstance(n, ast.Name):
                self.follow(name, n.id)

    def follow_attribute(self, name: str, m: _Module, head: str, attrs: list[str]) -> None:
        """``head.a.b`` in module m: a module alias's attribute, else ``head`` itself."""
        target = m.imports.get(head)
        if target is not None:
            module, attr = target
            dotted = module if attr is None else f"{module}.{attr}"
            for a in attrs:  # the longest module prefix, then the name in it
                if self.module(f"{dotted}.{a}") is None:
                    if self.module(dotted) is not None:
                        self.follow(dotted, a)
                    break
                dotted = f"{dotted}.{a}"
            else:
                if self.module(dotted) is not None:
                    self.needed.add(self.modules[dotted].path)  # type: ignore[union-attr]
        self.follow(name, head)

    def follow(self, name: str, symbol: str) -> None:
        """The definition of ``symbol`` in module ``name``, followed once."""
        if (name, symbol) in self.seen:
            return
        self.seen.add((name, symbol))
        m = self.module(name)
        if m is None:
            return
        if symbol in m.defs:
            self.needed.add(m.path)
            for node in m.defs[symbol]:
                value = (
                    node
                    if not isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign))
                    else node.value
                )
                if value is not None:
                    self.follow_node(name, m, value)
        if symbol in m.imports:
            module, attr = m.imports[symbol]
            if attr is None:
                if self.module(module) is not None:
                    self.needed.add(self.modules[module].path)  # type: ignore[union-attr]
                return
            sub = self.module(f"{module}.{attr}")
            if sub is not None:  # ``from . import layout``: the module itself
                self.needed.add(sub.path)
                return
            if self.module(module) is not None:
                self.needed.add(self.modules[module].path)  # type: ignore[union-attr]
                self.follow(module, attr)


def _cache_base() -> Path:
    for variable in ("NUMBA_CACHE_DIR", "XDG_CACHE_HOME"):
        if os.environ.get(variable):
            return Path(os.environ[variable]) / _CACHE_PARENT
    return Path.home() / ".cache" / _CACHE_PARENT


@lru_cache(maxsize=1)
def cache_directory() -> Path | None:
    """This source tree's cache folder (created), or None where none can be written."""
    base = _cache_base()
    folder = base / source_fingerprint()
    try:
        folder.mkdir(parents=True, exist_ok=True)
        os.utime(folder)  # marks it as in use for the pruning below
    except OSError:
        return None
    _prune(base, keep=folder)
    return folder


def _prune(base: Path, keep: Path) -> None:
    """Remove the cache folders of other source trees unused for ``STALE_AFTER_DAYS`` (and
    ``compiled_sources``' records as old)."""
    cutoff = time.time() - STALE_AFTER_DAYS * 86400
    with contextlib.suppress(OSError):
        for folder in base.iterdir():
            if folder == keep or folder.stat().st_mtime >= cutoff:
                continue
            if folder.is_dir():
                shutil.rmtree(folder, ignore_errors=True)
            elif folder.name.startswith("sources-"):  # ``compiled_sources``' records
                folder.unlink()


@contextlib.contextmanager
def _numba_cache_in(folder: Path) -> Iterator[None]:
    """Numba's cache folder while a function is decorated (its locator is chosen then)."""
    previous = numba.config.CACHE_DIR  # type: ignore[attr-defined]  # set at run time by numba
    numba.config.CACHE_DIR = str(folder)  # type: ignore[attr-defined]  # (as above)
    try:
        yield
    finally:
        numba.config.CACHE_DIR = previous  # type: ignore[attr-defined]  # (as above)


def compiled(**options: Any) -> Callable[[Callable], Any]:
    """``numba.njit(**options)`` with the package's cache (see the module docstring), e.g.
    ``compiled(error_model="numpy", inline="always")``."""

    def decorate(function: Callable) -> Any:
        folder = cache_directory()
        if folder is None:
            return njit(cache=False, **options)(function)
        with _numba_cache_in(folder):
            return njit(cache=True, **options)(function)

    return decorate


# --- borrowed arrays: no reference counting in the hot loops -----------------------------------
# Numba counts references to every array it passes, unpacks from a tuple or slices, with an
# atomic instruction each time (``lock xadd``). In the closed loop that is thousands per
# control sample; on an Intel Xeon it made the engine 1.8x slower than before the one-step
# redesign (on an AMD Zen 3, where uncontended atomics are cheaper, 1.03x). Switching
# atomicity off in Numba's runtime (a debugging flag) gave the same engine back its speed, so
# the loops work on *borrowed* arrays instead: views with no memory-info block, whose reference
# counting is a null test. A borrowed array must not outlive its owner: the loops borrow
# their arguments (held by the caller for the whole call) and their own scratch, which
# ``keep_alive`` holds to the end of the function; a borrowed array is never returned.


def _borrow_value(context: Any, builder: Any, ty: Any, value: Any) -> Any:
    if isinstance(ty, types.Array):
        owner = context.make_array(ty)(context, builder, value=value)
        view = context.make_array(ty)(context, builder)
        view.meminfo = cgutils.get_null_value(view.meminfo.type)
        view.parent = cgutils.get_null_value(view.parent.type)
        view.nitems = owner.nitems
        view.itemsize = owner.itemsize
        view.data = owner.data
        view.shape = owner.shape
        view.strides = owner.strides
        return view._getvalue()
    if isinstance(ty, types.BaseTuple):
        items = [
            _borrow_value(context, builder, member, builder.extract_value(value, i))
            for i, member in enumerate(ty.types)  # type: ignore[attr-defined]  # on each subclass
        ]
        return context.make_tuple(builder, ty, items)
    return value


@intrinsic
def borrowed(typingctx: Any, value: Any) -> Any:
    """In compiled code: ``value`` (an array, or a tuple of arrays and scalars, nested) as
    borrowed views of the same memory, which Numba does not reference-count (see above)."""

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return _borrow_value(context, builder, signature.args[0], args[0])

    return value(value), codegen


def _read_only_type(ty: Any) -> Any:
    """``ty`` with every array in it (a tuple's, a named tuple's, nested) typed read-only."""
    if isinstance(ty, types.Array):
        return ty.copy(readonly=True)
    if isinstance(ty, types.BaseTuple):
        members = [_read_only_type(m) for m in ty.types]  # type: ignore[attr-defined]
        if isinstance(ty, types.BaseNamedTuple):
            return types.BaseTuple.from_types(members, ty.instance_class)  # type: ignore[attr-defined]
        return types.BaseTuple.from_types(members)
    return ty


@intrinsic
def frozen(typingctx: Any, value: Any) -> Any:
    """In compiled code: an array (or a tuple or named record of arrays, nested) as a
    borrowed view (``borrowed``) typed read-only, so that callers holding the array writable
    or read-only select one signature of a callee that only reads it (one compilation, not
    two)."""
    kind = _read_only_type(value)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return _borrow_value(context, builder, signature.args[0], args[0])

    return kind(value), codegen


@intrinsic
def keep_alive(typingctx: Any, value: Any) -> Any:
    """In compiled code: a use of ``value`` that emits nothing, so that Numba keeps the owner
    of borrowed views alive up to this point (it frees an array after its last use)."""

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return context.get_dummy_value()

    return types.none(value), codegen


@intrinsic
def plain(typingctx: Any, value: Any) -> Any:
    """In compiled code: ``value`` typed as a plain value, not a literal (``True`` becomes a
    ``bool``, ``1`` an ``int64``): a compiled caller passing a constant then selects the same
    signature of the callee as a Python caller does (one compilation, not two)."""
    kind = types.unliteral(value)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return context.cast(builder, args[0], signature.args[0], kind)

    return kind(value), codegen


@intrinsic
def inline_here(typingctx: Any) -> Any:
    """In compiled code: mark the function being compiled ``alwaysinline`` for LLVM (no code).

    Numba links a callee's machine-independent code into each caller's module and optimises
    the whole, so LLVM then inlines the call as Numba's ``inline="always"`` would, but the
    callee is typed and lowered once, not once per call site (less compilation in a first run).
    Numba's own inlining stays where a caller's constant argument must prune a callee's branch."""

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        builder.function.attributes.add("alwaysinline")
        return context.get_dummy_value()

    return types.none(), codegen


@intrinsic
def restrict_arguments(typingctx: Any) -> Any:
    """In compiled code: mark every pointer argument of the function being compiled
    ``noalias`` for LLVM (no code), as Numba compiles its own parallel kernels
    (``Flags.noalias``).

    LLVM then knows that the arrays the function receives do not overlap, so a loop over
    them vectorises without checking at run time that its reads and writes are apart (and
    keeps values in registers across stores). The caller's contract: no memory that the
    function writes through one argument is reached through another (separate arrays; a
    read-only array may be passed twice). Array arguments, tuples of them included, reach
    the function as one pointer per array (Numba flattens them). The arithmetic is the
    same: only the order of loads and stores may change."""

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        for argument in context.call_conv.get_arguments(builder.function):
            if isinstance(argument.type, ir.PointerType):
                argument.add_attribute("noalias")
        return context.get_dummy_value()

    return types.none(), codegen
