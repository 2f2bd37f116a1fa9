"""The course's library-call policy: which library routines each graded function may not use.

Grades measure your own work. For every function you write, the course names the
library routines that compute its answer (or its defining step), or the answer of
a graded function it builds on; those may not be called inside it, directly or
through helpers you wrote. Everything else stays allowed: numpy, general linear
algebra (``np.linalg.svd``, ``np.linalg.eigh``, ``scipy.linalg.cho_factor``...),
sparse matrices and solvers (``scipy.sparse.linalg.splu``, ``spsolve``),
general optimizers (``scipy.optimize.minimize``), graph tools
(``scipy.sparse.csgraph``), libigl's mesh measures (``igl.doublearea``,
``igl.internal_angles``...) and anything the notebook provides. Library routines
stay usable outside graded functions: pictures, experiments and your own checks.

The table is course data (:data:`OWN`, :data:`BUILDS_ON`), published in
``LIBRARY_POLICY.md`` (a test keeps both equal) and at the top of every notebook.

Each notebook's tests cell starts with ``watch(name)`` and ends with
``verdict(name)``, which fails with a message naming the routine if the function
used one the policy forbids while the cell ran (``check_notebook.py`` shows that
message); ``check(name, function, *args)`` does the same for one call. Grading does the same in the
sandboxed kernel, on the hidden inputs: :func:`install` wraps every listed routine
before the notebook's first cell runs (``igl`` and its extension module
``igl.pyigl_core``, the scipy modules and classes that define the others, and
their backends), so every way to reach it afterwards gets the wrapper: an alias
(``from igl import cotmatrix as c``, ``c = igl.cotmatrix`` at module level),
``getattr(igl, "cot" + "matrix")``, ``importlib.import_module``, the extension
module, a helper function, a re-import after ``del sys.modules[...]`` or a module
built again from its file (``importlib.util.module_from_spec``: CPython restores
an extension module's original functions then, so the loaders re-wrap every
module they build from the files watched).

A wrapper never raises and never changes a result. When called, it walks the
Python stack to the innermost frame that runs a graded function (as the
notebook's namespace holds it under its contract name) whose policy forbids the
routine, and records the pair (function, routine). A graded function whose
policy allows the routine does not count, so a helper called from a function
whose own policy forbids the routine is charged to that function once, and a
library call inside a function you merely call (your ``cotangent_laplacian``
inside ``arap_precompute``) is charged to the function that made it. A library
routine called by another wrapped routine is not recorded again. When the
graded function is not Python code the stack can show (an alias such as
``cotangent_laplacian = igl.cotmatrix``, a ``functools.partial``), the call is
charged to the function being checked or collected; so is a call from another
thread while a function is checked or collected (that thread's stack does not
show who handed it the work).

Boundary. This guards against ordinary shortcuts, not a determined attacker in
their own kernel: code that digs the original routine out of a wrapper's
closure or the garbage collector, calls the shared library through ``ctypes``,
calls the routine in a child process (whose records stay there),
executes a library's source text by hand, or edits this module's records is out
of scope (the registry lives in the student's process; the grader reads what it
reports as untrusted data, names of routines in this table only).
"""

from __future__ import annotations

import contextlib
import functools
import importlib
import importlib.machinery
import os
import sys
import threading
import types

__all__ = ["OWN", "BUILDS_ON", "declare", "forbidden", "check", "watch", "verdict", "install", "markdown", "violations", "reset", "message"]

# Routine groups. A routine is named as students write it; LOCATIONS says where it lives.
_EDGES = ("igl.edges", "igl.edge_topology", "igl.edge_flaps", "igl.unique_edge_map", "igl.unique_edge_map_lists")
_ROTATION_FIT = (
    "igl.polar_svd", "igl.polar_svd3x3", "igl.polar_dec", "igl.procrustes", "igl.fit_rotations",
    "igl.rigid_alignment", "igl.iterative_closest_point",
    "scipy.linalg.orthogonal_procrustes", "scipy.linalg.polar", "scipy.spatial.procrustes",
    "scipy.spatial.transform.Rotation.align_vectors", "scipy.spatial.transform.Rotation.from_matrix",
    "scipy.spatial.transform.RigidTransform.from_matrix",
)
_COT = ("igl.cotmatrix", "igl.cotmatrix_entries", "igl.cotmatrix_intrinsic", "igl.intrinsic_delaunay_cotmatrix")
_ARAP = ("igl.arap_precomputation", "igl.arap_solve")
_FIXED_SOLVE = ("igl.min_quad_with_fixed", "igl.min_quad_with_fixed_precompute", "igl.min_quad_with_fixed_solve")
_DUAL_QUATERNIONS = ("scipy.spatial.transform.RigidTransform.as_dual_quat", "scipy.spatial.transform.RigidTransform.from_dual_quat")

#: function -> the routines that compute its answer or its defining step
OWN: dict[str, tuple[str, ...]] = {
    # 00 meshes
    "edges": _EDGES,
    "euler_characteristic": ("igl.euler_characteristic",),
    "boundary_loop_count": ("igl.boundary_loop", "igl.boundary_loop_all"),
    "genus": (),
    # 01 shape matching
    "centroid": (),
    "covariance_matrix": (),
    "optimal_orthogonal": _ROTATION_FIT,
    "orthogonal_align": (),
    # 02 sign correction
    "optimal_rotation": _ROTATION_FIT,
    "rigid_align": (),
    # 02b k-harmonic deformation (the notebook builds L and M with igl.cotmatrix and igl.massmatrix: allowed)
    "k_harmonic_operator": ("igl.harmonic_integrated_from_laplacian_and_mass",),
    "k_harmonic_precompute": ("igl.harmonic",) + _FIXED_SOLVE,
    "k_harmonic_solve": ("igl.harmonic",) + _FIXED_SOLVE,
    # 03 ARAP
    "cotangent_weights": _COT,
    "cotangent_laplacian": _COT,
    "arap_covariances": _ARAP,
    "arap_rotations": (),
    "arap_energy": _ARAP,
    "arap_precompute": _ARAP + _FIXED_SOLVE,
    "arap_global_step": _ARAP + _FIXED_SOLVE,
    "arap_solve": (),
    "laplacian_editing": (),
    # 04 BBW (igl.massmatrix is part of biharmonic_matrix's definition in the contract: allowed there)
    "biharmonic_matrix": ("igl.harmonic_integrated_from_laplacian_and_mass",),
    "handle_constraints": ("igl.boundary_conditions",),
    "inverse_distance_weights": (),
    "unconstrained_biharmonic_weights": ("igl.harmonic", "igl.biharmonic_coordinates") + _FIXED_SOLVE,
    "bbw": ("igl.bbw", "igl.active_set"),
    # 05 LBS and dual quaternions (converting a rotation matrix to a quaternion and back is allowed)
    "lbs_matrix": ("igl.lbs_matrix",),
    "lbs": (),
    "dual_quaternions": _DUAL_QUATERNIONS,
    "dual_quaternion_transforms": _DUAL_QUATERNIONS,
    "dqs": (),
    # 06 FAST
    "rotation_clusters": ("scipy.cluster.vq.kmeans", "scipy.cluster.vq.kmeans2"),
    "fast_precompute": _ARAP + _FIXED_SOLVE,
    "fast_energy": (),
    "fast_rotations": (),
    "fast_global_step": (),
    "fast_solve": (),
    # 07 tetrahedra
    "tet_volumes": ("igl.volume",),
    "tet_cotangent_laplacian": ("igl.cotmatrix", "igl.cotmatrix_entries", "igl.grad"),
    "tet_mass_matrix": ("igl.massmatrix",),
    "deformation_gradients": ("igl.grad",),
    "tet_arap_rotations": _ROTATION_FIT,
    "tet_arap_energy": (),
    "tet_arap_precompute": _ARAP + _FIXED_SOLVE,
    "tet_arap_global_step": (),
    "tet_biharmonic_matrix": ("igl.harmonic_integrated_from_laplacian_and_mass",),
}

#: function -> the graded functions it builds on: it may not use what they may not use either
BUILDS_ON: dict[str, tuple[str, ...]] = {
    "edges": (),
    "euler_characteristic": ("edges",),
    "boundary_loop_count": (),
    "genus": ("euler_characteristic", "boundary_loop_count"),
    "centroid": (),
    "covariance_matrix": ("centroid",),
    "optimal_orthogonal": (),
    "orthogonal_align": ("centroid", "covariance_matrix", "optimal_orthogonal"),
    "optimal_rotation": (),
    "rigid_align": ("centroid", "covariance_matrix", "optimal_rotation"),
    "k_harmonic_operator": (),
    "k_harmonic_precompute": (),
    "k_harmonic_solve": ("k_harmonic_precompute",),
    "cotangent_weights": (),
    "cotangent_laplacian": ("cotangent_weights",),
    "arap_covariances": ("cotangent_weights",),
    "arap_rotations": ("arap_covariances", "optimal_rotation"),
    "arap_energy": ("cotangent_weights",),
    "arap_precompute": ("cotangent_weights", "cotangent_laplacian"),
    "arap_global_step": ("arap_precompute",),
    "arap_solve": ("arap_rotations", "arap_global_step", "arap_energy"),
    "laplacian_editing": ("arap_precompute", "arap_global_step"),
    "biharmonic_matrix": ("cotangent_laplacian",),
    "handle_constraints": (),
    "inverse_distance_weights": (),
    "unconstrained_biharmonic_weights": ("biharmonic_matrix",),
    "bbw": ("unconstrained_biharmonic_weights",),
    "lbs_matrix": (),
    "lbs": ("lbs_matrix",),
    "dual_quaternions": (),
    "dual_quaternion_transforms": (),
    "dqs": ("dual_quaternions", "dual_quaternion_transforms"),
    "rotation_clusters": (),
    "fast_precompute": ("lbs_matrix", "cotangent_weights", "cotangent_laplacian"),
    "fast_energy": ("lbs", "arap_energy"),
    "fast_rotations": ("lbs", "arap_covariances", "optimal_rotation"),
    "fast_global_step": ("fast_precompute",),
    "fast_solve": ("fast_rotations", "fast_global_step", "fast_energy"),
    "tet_volumes": (),
    "tet_cotangent_laplacian": ("tet_volumes",),
    "tet_mass_matrix": ("tet_volumes",),
    "deformation_gradients": (),
    "tet_arap_rotations": ("deformation_gradients",),
    "tet_arap_energy": ("deformation_gradients", "tet_volumes"),
    "tet_arap_precompute": ("tet_cotangent_laplacian", "deformation_gradients", "tet_volumes"),
    "tet_arap_global_step": ("tet_arap_precompute",),
    "tet_biharmonic_matrix": ("tet_cotangent_laplacian", "tet_mass_matrix"),
}


@functools.cache
def forbidden(function: str) -> tuple[str, ...]:
    """The routines ``function`` may not use: its own (:data:`OWN`) and those of what it builds on.

    Parameters
    ----------
    function : str
        A graded function's name, e.g. ``"cotangent_laplacian"``.

    Returns
    -------
    tuple of str
        Routine names, sorted, e.g. ``("igl.cotmatrix", ...)``.
    """
    if function not in OWN:
        raise ValueError(f"{function!r} is not a graded function of the course")
    found = set(OWN[function])
    for base in BUILDS_ON[function]:
        found |= set(forbidden(base))
    return tuple(sorted(found))


#: every routine of the policy
ROUTINES: frozenset[str] = frozenset(r for routines in OWN.values() for r in routines)


def _backends(module: str, *names: str) -> tuple[str, ...]:
    return tuple(f"{module}_{kind}:{name}" for kind in ("cy", "xp") for name in names)


def _locations(routine: str) -> tuple[str, ...]:
    """Where ``routine`` lives: ``module:attribute`` or ``module:Class.method``, public home first."""
    if routine.startswith("igl."):
        name = routine[4:]
        return (f"igl:{name}", f"igl.pyigl_core:{name}")
    transform = "scipy.spatial.transform."
    if routine.startswith(transform + "Rotation."):
        method = routine.rsplit(".", 1)[1]
        return (f"scipy.spatial.transform._rotation:Rotation.{method}", *_backends("scipy.spatial.transform._rotation", method))
    if routine.startswith(transform + "RigidTransform."):
        method = routine.rsplit(".", 1)[1]
        return (f"scipy.spatial.transform._rigid_transform:RigidTransform.{method}",
                *_backends("scipy.spatial.transform._rigid_transform", method))
    module, name = routine.rsplit(".", 1)
    private = {"scipy.linalg.orthogonal_procrustes": "scipy.linalg._procrustes",
               "scipy.linalg.polar": "scipy.linalg._decomp_polar",
               "scipy.sparse.csgraph.laplacian": "scipy.sparse.csgraph._laplacian",
               "scipy.spatial.procrustes": "scipy.spatial._procrustes"}.get(routine)
    return (f"{module}:{name}",) + ((f"{private}:{name}",) if private else ())


#: the modules install() wraps routines in (imported first)
_MODULES: tuple[str, ...] = tuple(sorted({loc.split(":")[0] for r in ROUTINES for loc in _locations(r)}))
#: routine -> the graded functions whose policy forbids it
_FORBIDDEN_IN: dict[str, tuple[str, ...]] = {r: tuple(f for f in OWN if r in forbidden(f)) for r in ROUTINES}

def declare(own: dict, builds_on: dict | None = None) -> None:
    """Add the graded functions of another assignment to the policy (its course pack's ``[policy]`` table).

    Each notebook of such an assignment declares its table in the cell that installs
    the policy; the grader declares it on its side too. Routines of the new rows are
    wrapped where they live from then on, already imported modules included.

    Parameters
    ----------
    own : dict of str to sequence of str
        Function -> the routines that compute its answer or its defining step.
    builds_on : dict of str to sequence of str, optional
        Function -> the graded functions it builds on (each must be in the policy).

    Raises
    ------
    ValueError
        If a function is already in the policy with other routines, or builds on a function it does not know.
    """
    global ROUTINES, _MODULES, _FORBIDDEN_IN
    builds_on = builds_on or {}
    rows = {str(f): tuple(str(r) for r in routines) for f, routines in own.items()}
    bases = {str(f): tuple(str(b) for b in builds_on.get(f, ())) for f in rows}
    for f, routines in rows.items():
        if f in OWN and (tuple(OWN[f]), tuple(BUILDS_ON.get(f, ()))) != (routines, bases[f]):
            raise ValueError(f"the library policy already has {f!r} with other routines: {OWN[f]} (declared: {routines})")
    unknown = sorted({b for f in bases for b in bases[f]} - set(OWN) - set(rows))
    if unknown:
        raise ValueError(f"the library policy knows no graded function {unknown} to build on")
    if all(f in OWN for f in rows):
        return
    OWN.update(rows)
    BUILDS_ON.update(bases)
    forbidden.cache_clear()
    ROUTINES = frozenset(r for routines in OWN.values() for r in routines)
    _MODULES = tuple(sorted({loc.split(":")[0] for r in ROUTINES for loc in _locations(r)}))
    _FORBIDDEN_IN = {r: tuple(f for f in OWN if r in forbidden(f)) for r in ROUTINES}
    if _state.installed:  # wrap the new rows' routines in the modules already imported
        for name in _MODULES:
            module = sys.modules.get(name)
            if isinstance(module, types.ModuleType):
                _remember(module, name)
                _wrap_module(module, name)


#: cap on the pairs recorded (a loop calling a routine a million times records it once)
MAX_RECORDS = 256


class _State:
    def __init__(self):
        self.namespace: dict | None = None  # the notebook's namespace: contract name -> the student's function
        self.current: str | None = None  # the function being checked or collected
        self.found: list = []  # (function, routine) pairs
        self.installed = False
        self.files: dict = {}  # real path of a watched module's file -> its module name


_state = _State()
_local = threading.local()  # inside a wrapped routine: the routines it calls are not recorded again


def _code_of(obj) -> types.CodeType | None:
    """The code the stack shows when ``obj`` runs, without running any of the student's code."""
    for _ in range(8):
        if isinstance(obj, types.FunctionType):
            # a wrapper's frame is the library's, not the student's (and all wrappers share one code)
            return None if "__deformlab_routine__" in obj.__dict__ else obj.__code__
        if isinstance(obj, types.MethodType):
            obj = obj.__func__
        elif isinstance(obj, functools.partial):
            return None  # a partial of a library routine has no frame of its own
        else:
            return None
    return None


def _is_alias(obj, wrapper) -> bool:
    """Whether ``obj`` is ``wrapper`` itself, bound (a classmethod) or partially applied."""
    for _ in range(8):
        if obj is wrapper:
            return True
        if isinstance(obj, types.MethodType):
            obj = obj.__func__
        elif isinstance(obj, functools.partial):
            obj = obj.func
        else:
            return False
    return False


def _charge(routine: str, wrapper) -> None:
    """Record (function, routine) for the graded function that called ``routine`` (module docstring)."""
    namespace, names = _state.namespace, _FORBIDDEN_IN.get(routine, ())
    if namespace is None or not names:
        return
    # a graded name bound to the routine itself: every call of it is a call of that function
    charged = next((name for name in names if _is_alias(namespace.get(name), wrapper)), None)
    codes = {}
    for name in names if charged is None else ():
        code = _code_of(namespace.get(name))
        if code is not None:
            codes[code] = name
    frame = sys._getframe(2) if codes else None
    while frame is not None:
        charged = codes.get(frame.f_code)
        if charged is not None:
            break
        frame = frame.f_back
    del frame
    if charged is None and _state.current in names and (
        _code_of(namespace.get(_state.current)) is None or threading.current_thread() is not threading.main_thread()
    ):
        # the graded name is the routine itself (a partial of it, an object), or the call came from
        # another thread (whose stack does not show the function that handed it the work)
        charged = _state.current
    if charged is not None and (charged, routine) not in _state.found and len(_state.found) < MAX_RECORDS:
        _state.found.append((charged, routine))


def _wrapper(routine: str, original):
    def wrapped(*args, **kwargs):
        if getattr(_local, "inside", False):
            return original(*args, **kwargs)
        try:
            _charge(routine, wrapped)
        except Exception:  # noqa: BLE001 - the policy never breaks a call
            pass
        _local.inside = True
        try:
            return original(*args, **kwargs)
        finally:
            _local.inside = False

    # not functools.wraps: its __wrapped__ would hand out the original
    for attribute in ("__name__", "__qualname__", "__doc__", "__module__"):
        try:
            setattr(wrapped, attribute, getattr(original, attribute))
        except (AttributeError, TypeError):
            pass
    wrapped.__deformlab_routine__ = routine
    return wrapped


def _wrap_location(module: types.ModuleType, attribute: str, routine: str) -> None:
    owner_name, _, name = attribute.rpartition(".")
    owner = getattr(module, owner_name, None) if owner_name else module
    if owner is None:
        return
    if isinstance(owner, type):
        raw = owner.__dict__.get(name)
        if isinstance(raw, classmethod):
            if not hasattr(raw.__func__, "__deformlab_routine__"):
                setattr(owner, name, classmethod(_wrapper(routine, raw.__func__)))
        elif isinstance(raw, staticmethod):
            if not hasattr(raw.__func__, "__deformlab_routine__"):
                setattr(owner, name, staticmethod(_wrapper(routine, raw.__func__)))
        elif callable(raw) and not hasattr(raw, "__deformlab_routine__"):
            setattr(owner, name, _wrapper(routine, raw))
        return
    current = owner.__dict__.get(name) if isinstance(owner, types.ModuleType) else None
    if callable(current) and not hasattr(current, "__deformlab_routine__"):
        setattr(owner, name, _wrapper(routine, current))


def _wrap_module(module: types.ModuleType, name: str | None = None) -> None:
    """Wrap every routine of the policy that lives in ``module`` (known as ``name``)."""
    name = name or getattr(module, "__name__", None)
    for routine in ROUTINES:
        for location in _locations(routine):
            home, attribute = location.split(":")
            if home == name:
                _wrap_location(module, attribute, routine)


def _watched_name(module) -> str | None:
    name = getattr(module, "__name__", None)
    if name in _MODULES:
        return name
    path = getattr(module, "__file__", None)
    if isinstance(path, str):
        with contextlib.suppress(OSError, ValueError):
            return _state.files.get(os.path.realpath(path))
    return None


def _rewrapping(method):
    """A loader method that wraps the policy's routines in the module it built or ran, if watched."""

    def run(self, *args, **kwargs):
        result = method(self, *args, **kwargs)
        module = result if isinstance(result, types.ModuleType) else (args[0] if args else None)
        try:
            watched = _watched_name(module)
            if watched is not None:
                _remember(module, watched)
                _wrap_module(module, watched)
        except Exception:  # noqa: BLE001 - an import never fails because of the policy
            pass
        return result

    run.__deformlab_routine__ = "loader"
    return run


def _patch_loaders() -> None:
    machinery = importlib.machinery
    patches = ((machinery.ExtensionFileLoader, "create_module"), (machinery.ExtensionFileLoader, "exec_module"),
               (machinery.SourceFileLoader, "exec_module"), (machinery.SourcelessFileLoader, "exec_module"))
    for cls, method in patches:
        current = getattr(cls, method)
        if not hasattr(current, "__deformlab_routine__"):
            setattr(cls, method, _rewrapping(current))


def install(namespace: dict | None = None) -> None:
    """Wrap every routine of the policy, where it lives, so its calls from graded functions are recorded.

    Idempotent; wrappers never raise and return what the routine returns.

    Parameters
    ----------
    namespace : dict, optional
        The notebook's namespace (contract name -> the student's function): IPython's
        user namespace when running in IPython, else ``__main__``'s.
    """
    if namespace is None and _state.namespace is None:
        namespace = _notebook_namespace()
    if namespace is not None:
        _state.namespace = namespace
    if _state.installed:
        return
    # The loaders wrap every watched module they build from now on (a first import, a re-import,
    # a module built from its file); the modules already imported are wrapped here.
    _patch_loaders()
    for name in _MODULES:
        module = sys.modules.get(name)
        if isinstance(module, types.ModuleType):
            _remember(module, name)
            _wrap_module(module, name)
    _state.installed = True


def _remember(module: types.ModuleType, name: str) -> None:
    """Know ``module``'s file as ``name``'s, so a module built again from it under any name is wrapped too."""
    path = getattr(module, "__file__", None)
    if isinstance(path, str):
        _state.files[os.path.realpath(path)] = name


def _notebook_namespace() -> dict | None:
    ipython = sys.modules.get("IPython")  # running in IPython means it is imported already
    shell = ipython.get_ipython() if ipython is not None else None
    if shell is not None:
        return shell.user_ns
    main = sys.modules.get("__main__")
    return vars(main) if main is not None else None


def load_ipython_extension(ipython) -> None:
    """IPython extension hook: the grading kernel loads this module before the notebook's first cell."""
    install(ipython.user_ns)


def reset(namespace: dict | None = None, function: str | None = None) -> None:
    """Forget what was recorded; then record for ``namespace``'s functions while ``function`` is collected."""
    if namespace is not None:
        _state.namespace = namespace
    _state.current = function
    _state.found = []


def violations(function: str | None = None) -> list:
    """The routines charged to ``function`` since :func:`reset` (all ``(function, routine)`` pairs if None)."""
    if function is None:
        return list(_state.found)
    return [routine for charged, routine in _state.found if charged == function]


def message(function: str, routine: str) -> str:
    """What a student reads when ``function`` calls ``routine``."""
    if routine in OWN.get(function, ()):
        why = "which computes its answer or its defining step"
    else:
        base = next((b for b in _bases(function) if routine in OWN[b]), None)
        why = f"which computes what your {base} computes (call your own {base})" if base else "which computes a graded answer"
    return f"{function} calls {routine}, {why}: the course's library policy (LIBRARY_POLICY.md) does not allow it here"


def _bases(function: str) -> list[str]:
    found = []
    for base in BUILDS_ON.get(function, ()):
        found += [base, *_bases(base)]
    return found


def check(function: str, implementation, *args, **kwargs):
    """Call ``implementation(*args, **kwargs)`` as graded function ``function`` and enforce the policy.

    Parameters
    ----------
    function : str
        The graded function's contract name, e.g. ``"cotangent_laplacian"``.
    implementation : callable
        Your function (normally the one the notebook holds under that name).

    Returns
    -------
    object
        What the call returned.

    Raises
    ------
    AssertionError
        Naming the first library routine the policy does not allow in ``function``
        that the call used.
    """
    if function not in OWN:
        raise ValueError(f"{function!r} is not a graded function of the course")
    install()
    namespace = dict(sys._getframe(1).f_globals)
    namespace[function] = implementation
    saved = (_state.namespace, _state.current, _state.found)
    _state.namespace, _state.current, _state.found = namespace, function, []
    try:
        result = implementation(*args, **kwargs)
        used = violations(function)
    finally:
        _state.namespace, _state.current, _state.found = saved
    if used:
        raise AssertionError(message(function, used[0]))
    return result


def watch(function: str) -> None:
    """Start recording, for a tests cell, the routines ``function`` calls that the policy forbids in it.

    The tests cell then calls the notebook's functions as usual and ends with :func:`verdict`.
    """
    if function not in OWN:
        raise ValueError(f"{function!r} is not a graded function of the course")
    install()
    _state.namespace, _state.current, _state.found = sys._getframe(1).f_globals, function, []


def verdict(function: str) -> None:
    """End a :func:`watch`: fail naming the first routine the policy forbids that ``function`` called.

    Raises
    ------
    AssertionError
        With :func:`message`'s text.
    """
    used = violations(function)
    _state.current, _state.found = None, []
    if used:
        raise AssertionError(message(function, used[0]))


def markdown(functions) -> str:
    """The policy of ``functions`` as a markdown section (each notebook's first text shows it)."""
    lines = [
        "**Library policy.** Grades measure your own work: inside the functions you write, the library",
        "routines below may not be used (directly or through helpers you wrote), because they compute",
        "the function's answer, its defining step, or the answer of a function it builds on",
        "(`LIBRARY_POLICY.md`). A function that calls one scores 0, with a message naming the call;",
        "each tests cell checks it. numpy, general linear algebra (SVD, eigen-decompositions), sparse",
        "solvers and general optimizers stay allowed, and so does any library outside your functions",
        "(pictures, experiments, checks).",
        "",
        "| function | may not use |",
        "|---|---|",
    ]
    for function in functions:
        routines = forbidden(function)
        lines.append(f"| `{function}` | " + (", ".join(f"`{r}`" for r in routines) if routines else "no restriction") + " |")
    return "\n".join(lines)
