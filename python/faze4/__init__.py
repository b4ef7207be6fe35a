"""faze4: can the motors of a real arm follow this trajectory?

A fast, exact dynamics simulator of the Faze4 six-axis arm (or any URDF arm) under a 5 kHz
digital PD controller, from Python::

    import faze4, numpy as np
    robot = faze4.Robot.faze4()
    run = faze4.wave(robot, duration=8.0, amp_deg=25.0)
    run.follows, run.summary["max_tracking_error_rad"], run.q.shape

Every option of the command line is a keyword of ``wave``, ``replay``, ``shape``, ``retime``, ``sweep`` and
``find``: the same name with underscores, the same default, the same checks, both declared once
by the library. The keywords fill the library's own run configuration, field by field, and the
run is the binary's: its summary equals the binary's ``--summary`` JSON. Messages name options as
keywords (``dt``) where the binary names flags (``--dt``). The library writes no file it is not
asked for: the trail is in ``Run.t``, ``Run.q``, ... (give ``trail`` a path to write the CSV too;
the binary writes ``faze4_trail.csv`` by default). One default differs, because a Python call
returns what the binary prints: ``quiet=True`` (nothing is printed; ``quiet=False`` prints the
progress lines).
Bad input raises :class:`Error`; a value of the wrong type raises ``TypeError``; with
``strict=True`` a run whose arm does not follow raises :class:`CannotFollow`, which carries the
run. A :class:`Robot` pickles and copies (by its options), so it goes to ``multiprocessing``
workers.
"""

from __future__ import annotations

import inspect
import json
import os
import sys
from collections import namedtuple
from typing import Any

import numpy as np

from . import _faze4
from ._faze4 import Error, __version__

__all__ = [
    "Error",
    "CannotFollow",
    "Robot",
    "Run",
    "Retimed",
    "Found",
    "Option",
    "wave",
    "replay",
    "shape",
    "retime",
    "sweep",
    "find",
    "options",
    "__version__",
]


def __dir__() -> list[str]:
    """The public API only (``__all__``)."""
    return sorted(__all__)


class CannotFollow(Error):
    """A run with ``strict=True`` whose arm does not follow its command (the binary's exit
    status 3): the message is the verdict line; ``run`` is the :class:`Run`."""

    def __init__(self, verdict: str, run: Run | None = None):
        super().__init__(verdict)
        self.run = run

    def __reduce__(self):
        return (CannotFollow, (str(self), self.run))

#: An option of a command as the library declares it (``long``: the binary's flag, without ``--``).
Option = namedtuple("Option", "name long kind repeated required default choices help")

#: Python's defaults where they differ from the library's (see the module's docstring).
PYTHON_DEFAULTS = {"quiet": True}

_RUN_COMMANDS = ("wave", "replay", "shape")


def _table(command: str) -> dict[str, Option]:
    return {
        name: Option(name, name.replace("_", "-"), kind, repeated, required, default, choices, help_)
        for (name, kind, repeated, required, default, choices, help_) in _faze4._options(command)
    }


_TABLES = {c: _table(c) for c in (*_RUN_COMMANDS, "retime", "run")}


def options(command: str) -> list[Option]:
    """The keywords of ``command`` ('wave', 'replay', 'shape', 'retime'; 'run': those every run
    command shares, which ``Robot``, ``Robot.faze4`` and ``Robot.from_urdf`` take), as the library declares
    them: name, long option, kind, default, choices, help."""
    if command not in _TABLES:
        raise Error(f"no command '{command}' (wave, replay, shape, retime, run)")
    return list(_TABLES[command].values())


def _text(value: Any) -> str:
    """A number as the binary's ``--vary`` writes it (floats exactly: repr round-trips)."""
    if isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_)):
        return str(int(value))
    return repr(float(value))


def _given(options: dict[str, Any]) -> dict[str, Any]:
    """The keywords given a value: ``None`` means the option's default."""
    return {name: value for name, value in options.items() if value is not None}


class Robot(_faze4.Robot):
    """An arm: its model (as the binary loads it from the same options) and a dynamics
    workspace. ``faze4.Robot(robot="ur.urdf.xacro", xacro_arg=["ur_type:=ur5e"])`` reads a
    robot file (URDF, xacro or MJCF, told apart by their root element); :meth:`Robot.faze4` is the bundled
    arm and :meth:`Robot.from_urdf` a robot file by its path.

    The dynamics take and return float64 numpy arrays, one joint per entry, SI units, as
    Pinocchio does: ``mass_matrix(q)``, ``gravity(q)``, ``rnea(q, v, a)``, ``aba(q, v, tau)``,
    ``frame_pose(q, link)``. The robot's options (``motors``, ``rotor_inertia``,
    ``gear_ratio``, ``payload_kg``, ``no_gravity``, ...) change the model of these calls as they
    change a run's, and every run of the robot starts from them."""

    _options: dict[str, Any]

    def __new__(cls, **options: Any) -> Robot:
        """The arm the keywords describe: the options every run command shares
        (``faze4.options('run')``): ``robot`` (a URDF, xacro or MJCF file; ``urdf`` is its old name),
        ``xacro_arg``, ``package_path``, ``motors``, ... Without ``robot``, the bundled Faze4."""
        return cls._load(options)

    @classmethod
    def faze4(cls, **options: Any) -> Robot:
        """The bundled Faze4 (the binary's default arm). Keywords: the options every run command
        shares (``faze4.options('run')``), e.g. ``motors='faze4'``, ``payload_kg=0.5``."""
        return cls._load(options)

    @classmethod
    def from_urdf(
        cls,
        path: str | os.PathLike[str],
        package_path: list[str | os.PathLike[str]] | None = None,
        tool_link: str | None = None,
        **options: Any,
    ) -> Robot:
        """The arm of a robot file: a URDF, a xacro file or a MuJoCo MJCF model, told apart by their
        root element (docs/robots.md); ``package_path``: where ``package://`` meshes and xacro's
        ``$(find PKG)`` are looked for (ROS_PACKAGE_PATH after); ``tool_link``: the link traced as
        the tool. Other keywords: as :meth:`Robot.faze4` (``xacro_arg=["NAME:=VALUE", ...]`` for a
        xacro file)."""
        if not isinstance(path, (str, os.PathLike)):
            # None would load the bundled arm, not the file meant (Robot.faze4() is that)
            raise TypeError(f"from_urdf: path is {type(path).__name__}, not a path (Robot.faze4() is the bundled arm)")
        return cls._load(dict(robot=path, package_path=package_path, tool_link=tool_link, **options))

    @classmethod
    def _load(cls, options: dict[str, Any]) -> Robot:
        table = _TABLES["run"]
        options = _renamed(options)
        for name in options:
            if name not in table:
                raise Error(
                    f"{name}: not an option a robot takes (the options every run command shares: {', '.join(table)})"
                )
        options = _given(options)
        robot = _faze4.Robot.__new__(cls, options)
        robot._options = options
        return robot

    def __reduce__(self):
        # pickled and copied by its options: the model is read again from them
        return (_robot, (type(self), dict(getattr(self, "_options", {}))))


#: Options' old names as the library declares them: ``urdf`` is ``robot``.
_OLD_NAMES = dict(_faze4._old_names())


def _renamed(options: dict[str, Any]) -> dict[str, Any]:
    """``options`` with each old name replaced by its option's name (``urdf`` by ``robot``);
    both given is an error."""
    renamed = dict(options)
    for old, new in _OLD_NAMES.items():
        if old in renamed:
            if renamed.get(new) is not None and renamed[old] is not None:
                raise Error(f"{old}: is {new}'s old name: give one of them")
            value = renamed.pop(old)
            if renamed.get(new) is None:
                renamed[new] = value
    return renamed


def _robot(cls: type[Robot], options: dict[str, Any]) -> Robot:
    return cls._load(options)


class Run:
    """What a run did.

    ``summary``: the binary's ``--summary`` JSON as a dict; ``follows``: whether the arm follows
    its command; ``verdict``: the verdict, ``"follows"``, ``"collides"`` or ``"cannot follow"``;
    ``verdict_line``: the line the binary prints last (``"verdict: follows"``, or the verdict
    and its reasons); ``reasons``: why not;
    ``t`` (N,), ``q`` (N, dof), ``q_cmd`` (N, dof), ``tool_xyz`` (N, 3): the trail's samples
    (every ``record_period``, t = 0 and the last step included); ``warnings``: what the binary
    would have said on stderr. A run that diverged returns too: ``summary["diverged"]``."""

    __slots__ = (
        "summary",
        "follows",
        "verdict",
        "verdict_line",
        "reasons",
        "t",
        "q",
        "q_cmd",
        "tool_xyz",
        "warnings",
        "_engine_s",
    )

    def __init__(self, summary_json, verdict_line, t, q, q_cmd, tool_xyz, warnings, engine_s):
        self.summary = json.loads(summary_json)
        self.follows = bool(self.summary["verdict"]["follows"])
        self.reasons = list(self.summary["verdict"]["reasons"])
        self.verdict_line = verdict_line
        # the word after "verdict: ", up to its reasons: the first of "collides — …; cannot follow — …"
        self.verdict = verdict_line.removeprefix("verdict: ").split(" — ")[0]
        self.t, self.q, self.q_cmd, self.tool_xyz = t, q, q_cmd, tool_xyz
        self.warnings = warnings
        # seconds the binary's own scenario-run-outputs code took (tools/bench/python_api.py)
        self._engine_s = engine_s

    def __repr__(self) -> str:
        return f"<faze4.Run {self.verdict_line!r}, {len(self.t)} samples>"


def _robot_options(robot: Robot) -> dict[str, Any]:
    if not isinstance(robot, _faze4.Robot):
        raise TypeError(f"robot: expected a faze4.Robot, got {type(robot).__name__}")
    return dict(getattr(robot, "_options", {}))


def _q_traj(q_traj: Any, name: str = "q_traj"):
    """A replay's trajectory (a retime's path): a path (the binary reads it) or an array-like
    (N, dof) of real numbers, converted exactly to float64 (any order and strides)."""
    if isinstance(q_traj, (str, os.PathLike)):
        return os.fspath(q_traj), None
    return name, _real_array(name, q_traj, 2, "(N, dof), one row per frame")


def _real_array(name: str, value: Any, ndim: int, expected: str) -> np.ndarray:
    """``value`` as a float64 array of ``ndim`` dimensions (``expected`` says which shape),
    converted exactly from any real number type, in any order and strides."""
    array = np.asarray(value)
    if array.dtype.kind not in "fiu":
        raise TypeError(f"{name}: dtype {array.dtype} is not a real number type (float64 expected)")
    if array.ndim != ndim:
        raise Error(f"{name}: shape {array.shape}; expected {expected}")
    _faze4._check_array(name, array.shape)  # the .npy cap, before a float64 copy is made
    return array.astype(np.float64, copy=False)


def _options(command: str, robot: Robot, options: dict[str, Any]) -> dict[str, Any]:
    """The keywords of a run: Python's defaults, then the robot's, then the call's (each one a
    keyword of ``command``, as a Python function's would be)."""
    table = _TABLES[command]
    options = _renamed(options)
    for name in options:
        if name not in table:
            raise TypeError(f"{command}() got an unexpected keyword argument '{name}'")
    return {**PYTHON_DEFAULTS, **_robot_options(robot), **_given(options)}


def _timed(path: str, frames, t: Any, v: Any, a: Any, joint_names: Any):
    """A replay's time stamps and what goes with them (``t``, ``v``, ``a``, ``joint_names``), as
    the binding takes them; ``None`` without ``t``."""
    if t is None:
        for name, given in (("v", v), ("a", a), ("joint_names", joint_names)):
            if given is not None:
                raise Error(f"{name}: goes with the time stamps t=")
        return None
    if frames is None:
        raise Error(f"t: time stamps go with positions given as an array, not a file ({path}: its own times)")

    def real(name: str, value: Any, ndim: int):
        if value is None:
            return None
        return np.ascontiguousarray(_real_array(name, value, ndim, "(N,)" if ndim == 1 else "(N, J)"))

    names = None if joint_names is None else [str(n) for n in joint_names]
    return (real("t", t, 1), real("v", v, 2), real("a", a, 2), names)


#: What goes with a replay's positions when they are time-stamped.
_TIMED = ("t", "v", "a", "joint_names")


def _run(command: str, robot: Robot, options: dict[str, Any], frames=None, timed=None) -> Run:
    merged = _options(command, robot, options)
    quiet = bool(merged.get("quiet", True))
    if not quiet:
        sys.stdout.flush()  # the progress lines come from the binding, after what Python printed
    *fields, printed, diverged = _faze4._run(command, merged, frames, timed)
    return _reported(merged, Run(*fields), printed, diverged)


def _reported(merged: dict[str, Any], run: Run, printed: str, diverged: str | None = None) -> Run:
    """``run`` as the binary reports it: unless ``quiet``, its warnings on stderr, what it
    prints and its verdict on stdout, a divergence on stderr; under ``strict``, a run that does
    not follow raises :class:`CannotFollow`."""
    if not merged.get("quiet", True):
        for line in run.warnings:
            print(f"faze4: {line}", file=sys.stderr)
        print(printed + run.verdict_line, flush=True)
        if diverged:
            print(f"faze4: {diverged}", file=sys.stderr)
    if merged.get("strict") and not run.follows:
        raise CannotFollow(run.verdict_line, run)
    return run


def wave(robot: Robot, **options: Any) -> Run:
    return _run("wave", robot, options)


def replay(robot: Robot, q_traj: Any, t: Any = None, v: Any = None, a: Any = None, joint_names: Any = None, **options: Any) -> Run:
    path, frames = _q_traj(q_traj)
    timed = _timed(path, frames, t, v, a, joint_names)
    return _run("replay", robot, {**options, "q_traj": path}, frames, timed)


def shape(robot: Robot, shape: str, **options: Any) -> Run:
    return _run("shape", robot, {**options, "shape": shape})


class Retimed:
    """The fastest timing of a path that the motors follow, checked in the closed loop
    (``faze4 retime``, docs/retime.md).

    ``t`` (M,): the timing's times (s) at the grid points; ``q``, ``qd``, ``qdd`` (M, J): the
    positions, velocities and accelerations there, one column per name of ``joint_names`` (what
    ``out=`` writes, and what ``replay(robot, r.q, t=r.t, v=r.qd, a=r.qdd,
    joint_names=r.joint_names)`` plays); ``duration`` (s); ``own_duration``: the input's own
    timing (a time-stamped file's last time, a ``.npy``'s ``traj_period``) or ``None``;
    ``speedup``: ``own_duration / duration`` or ``None``; ``run``: the checked timing's
    :class:`Run` (its trail, summary and verdict); ``follows``, ``verdict``, ``verdict_line``: the run's;
    ``lines``: what the binary prints before its verdict (the duration, what binds where, the
    check)."""

    __slots__ = ("t", "q", "qd", "qdd", "joint_names", "duration", "own_duration", "run", "lines")

    def __init__(self, run: Run, timing, duration: float, own_duration: float | None, lines: str):
        self.t, self.q, self.qd, self.qdd, self.joint_names = timing
        self.duration = duration
        self.own_duration = own_duration
        self.run = run
        self.lines = lines

    @property
    def speedup(self) -> float | None:
        return None if self.own_duration is None else self.own_duration / self.duration

    @property
    def follows(self) -> bool:
        return self.run.follows

    @property
    def verdict(self) -> str:
        return self.run.verdict

    @property
    def verdict_line(self) -> str:
        return self.run.verdict_line

    def __repr__(self) -> str:
        return f"<faze4.Retimed {self.duration:.4f} s, {len(self.t)} points, {self.run.verdict_line!r}>"


def retime(robot: Robot, q_path: Any, **options: Any) -> Retimed:
    if "q_traj" in options:
        raise TypeError("retime() got an unexpected keyword argument 'q_traj' (the path is q_path)")
    path, frames = _q_traj(q_path, "q_path")
    merged = _options("retime", robot, {**options, "q_traj": path})
    quiet = bool(merged.get("quiet", True))
    if not quiet:
        sys.stdout.flush()
    try:
        (*fields, printed), timing, duration, own = _faze4._retime(merged, frames)
    except _faze4._NothingFollows as e:
        # no timing of the path follows: under strict the reason is what cannot be followed
        # (the binary's exit status 3), else bad input (status 2)
        raise (CannotFollow if merged.get("strict") else Error)(str(e)) from None
    run = _reported(merged, Run(*fields), printed)
    return Retimed(run, timing, duration, own, printed)


def _base(command: str, robot: Robot, options: dict[str, Any]):
    """A sweep's or a search's keywords, and a replay's arrays (``q_traj``, with ``t``, ``v``,
    ``a``, ``joint_names`` for a time-stamped one)."""
    if command not in _RUN_COMMANDS:
        raise Error(f"command: '{command}' is not one of wave, replay, shape")
    frames = timed = None
    if command == "replay":
        if "q_traj" not in options:
            raise Error("q_traj: a replay sweep needs q_traj=")
        arrays = {k: options.pop(k, None) for k in _TIMED}
        path, frames = _q_traj(options["q_traj"])
        timed = _timed(path, frames, **arrays)
        options = {**options, "q_traj": path}
    return _options(command, robot, options), frames, timed


def _row(names, values, summary_json, failure) -> dict[str, Any]:
    row = json.loads(summary_json) if summary_json is not None else {"failed": failure}
    row.update(zip(names, values))
    return row


def sweep(
    robot: Robot, command: str, vary: dict[str, Any], jobs: int = 0, own_clearance: bool = False, **options: Any
) -> list[dict[str, Any]]:
    merged, frames, timed = _base(command, robot, dict(options))
    if not vary:
        raise Error("vary: nothing to vary: give vary={'payload_kg': [...]}")
    specs = []
    for name, values in vary.items():
        if isinstance(values, str):
            text = values
        else:
            array = np.asarray(values, dtype=np.float64)
            if array.ndim != 1:
                raise Error(f"vary: {name}: shape {array.shape}; give a list of values")
            text = ",".join(_text(v) for v in array)
        specs += [f"{name}={text}"]
    rows, warnings = _faze4._sweep(command, merged, list(_given(_renamed(options))), specs, int(jobs), bool(own_clearance), frames, timed)
    names = list(vary)
    return [_row(names, *r) for r in rows]


def find(
    robot: Robot,
    command: str,
    name: str,
    lo: float,
    hi: float,
    resolution: float | None = None,
    smallest: bool = False,
    jobs: int = 0,
    own_clearance: bool = False,
    **options: Any,
) -> Found:
    merged, frames, timed = _base(command, robot, dict(options))
    resolution = None if resolution is None else float(resolution)
    kind, line, follows, fails, warnings = _faze4._find(
        command, merged, list(_given(_renamed(options))), name, float(lo), float(hi), resolution, bool(smallest), int(jobs), bool(own_clearance), frames, timed
    )
    follows_row = _row([name], *follows) if follows else None
    fails_row = _row([name], *fails) if fails else None
    reason = ""
    if fails_row is not None:
        reason = fails_row.get("failed") or "; ".join(fails_row["verdict"]["reasons"])
        if "failed" in fails_row:
            reason = f"failed: {reason}"
    return Found(
        name=name,
        found=kind,
        value=follows_row[name] if kind == "boundary" else None,
        fails_at=fails_row[name] if fails_row is not None else None,
        reason=reason,
        line=line,
        follows=follows_row,
        fails=fails_row,
        warnings=warnings,
    )


class Found:
    """What :func:`find` found.

    ``value``: the value of option ``name`` found (None unless the boundary is inside the
    range); ``fails_at`` and ``reason``: the next value and why the arm does not follow there;
    ``found``: 'boundary', 'none_follows' or 'all_follow'; ``line``: the line the binary prints;
    ``follows`` and ``fails``: the two runs' summaries (dicts, as ``Run.summary``, with the
    value under ``name``; a run that could not be built: {'failed': reason}); ``warnings``."""

    __slots__ = ("name", "found", "value", "fails_at", "reason", "line", "follows", "fails", "warnings")

    def __init__(self, **fields: Any):
        for key in self.__slots__:
            setattr(self, key, fields[key])

    def __repr__(self) -> str:
        if self.found == "boundary":
            return f"<faze4.Found {self.name} = {self.value!r}; fails at {self.fails_at!r}: {self.reason}>"
        if self.found == "none_follows":
            return f"<faze4.Found none follows: {self.name} = {self.fails_at!r} fails: {self.reason}>"
        value = self.follows[self.name] if self.follows else None
        return f"<faze4.Found all follow, up to {self.name} = {value!r}>"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Found) and all(getattr(self, k) == getattr(other, k) for k in self.__slots__)


# --- docstrings and signatures from the library's declarations, built at import ---------------

_ABOUT = {
    "wave": "Every joint follows A·sin(ω t + i·π/3) (docs/model.md): ``faze4 wave``.",
    "replay": "Replay a joint trajectory: ``faze4 replay``.\n\n"
    "``q_traj``: an array-like (N, dof) of joint positions (rad or m), repeating every ``traj_period``, "
    "or the path of a file: .npy frames, or a time-stamped trajectory (.yaml, .json, .mcap, .csv; "
    "docs/trajectories.md). ``t``: time stamps (N,) in s from the start, which make ``q_traj`` an "
    "(N, J) time-stamped trajectory played as ros2_control's joint_trajectory_controller plays one, "
    "with optional velocities ``v`` and accelerations ``a`` (N, J) and ``joint_names`` (J names of "
    "the model's joints, any order and any subset; default: the model's joints in order).",
    "shape": "Draw a sine, circle or triangle on the board (exact IK, then the samples as a loop): "
    "``faze4 shape``.\n\n``shape``: 'sine', 'circle' or 'tri'.",
    "retime": "The fastest timing of a path that the motors follow, checked in the closed loop: "
    "``faze4 retime`` (docs/retime.md).\n\n``q_path``: an array-like (N, dof) of joint positions "
    "(the path's points, the model's joints in order), or the path of a file ``replay`` reads "
    "(its times ignored). Returns a :class:`Retimed`; with ``strict=True`` a path that no timing "
    "follows, or a checked timing that does not, raises :class:`CannotFollow`.",
}


def _default(option: Option):
    if option.name in PYTHON_DEFAULTS:
        return PYTHON_DEFAULTS[option.name]
    if option.kind == "flag":
        return False
    if option.default is None:
        return None
    if option.kind == "float":
        return float(option.default)
    if option.kind == "int":
        return int(option.default)
    return option.default


def _doc_lines(table: dict[str, Option], skip=()) -> list[str]:
    lines = []
    for option in table.values():
        if option.name in skip:
            continue
        default = _default(option)
        choices = f" One of {', '.join(repr(c) for c in option.choices)}." if option.choices else ""
        binary = option.default if option.kind != "flag" else False
        differs = " (the binary's: %r)" % (binary,) if option.name in PYTHON_DEFAULTS else ""
        text = option.help.rstrip(".") + "."
        lines.append(f"    {option.name} ({option.kind}, default {default!r}{differs}): {text}{choices}")
    return lines


def _document(
    function, command: str, positional: tuple[str, ...], optional: tuple[str, ...] = (), skip: tuple[str, ...] = ()
) -> None:
    """``function``'s doc and signature from the options of ``command``; ``skip``: options the
    function takes under another name (a positional one). Its first argument, ``robot``, is the
    :class:`Robot`, whose own option ``robot`` (the robot file) a run does not take."""
    table = {name: option for name, option in _TABLES[command].items() if name not in skip and name != "robot"}
    returns = "Retimed" if command == "retime" else "Run"
    lines = [
        _ABOUT[command],
        "",
        "Returns a :class:`%s`. Keywords (every option of ``faze4 %s``, same name with underscores):" % (returns, command),
        "",
        *_doc_lines(table, skip=positional),
    ]
    function.__doc__ = "\n".join(lines)
    parameters = [inspect.Parameter("robot", inspect.Parameter.POSITIONAL_OR_KEYWORD)]
    parameters += [inspect.Parameter(p, inspect.Parameter.POSITIONAL_OR_KEYWORD) for p in positional]
    parameters += [inspect.Parameter(p, inspect.Parameter.POSITIONAL_OR_KEYWORD, default=None) for p in optional]
    parameters += [
        inspect.Parameter(o.name, inspect.Parameter.KEYWORD_ONLY, default=_default(o))
        for o in table.values()
        if o.name not in positional
    ]
    function.__signature__ = inspect.Signature(parameters)


_document(wave, "wave", ())
_document(replay, "replay", ("q_traj",), _TIMED)
_document(shape, "shape", ("shape",))
_document(retime, "retime", ("q_path",), skip=("q_traj",))

_VARIED, _SCALES = _faze4._varied()
sweep.__doc__ = "\n".join(
    [
        "Many runs of ``command`` ('wave', 'replay', 'shape') on every core, the GIL released: "
        "``faze4 sweep --vary``.",
        "",
        "``vary``: {name: values} (an array-like, or 'LO:HI:STEP'); the runs are the product. "
        "A name is a numeric option of the command (%s) or a multiplier: %s. ``jobs``: threads "
        "(0: one per core). ``own_clearance``: each run its own self-clearance, not the commanded "
        "path's shared (docs/sweep.md). Other keywords: the options of the command (see "
        "``help(faze4.wave)``)." % (", ".join(_VARIED), ", ".join(_SCALES)),
        "",
        "Returns one dict per run, in grid order: the run's summary (as ``Run.summary``) with "
        "the varied values under their names; a run that could not be built: {'failed': reason}.",
    ]
)
find.__doc__ = (
    "The largest value of option ``name`` in [lo, hi] at which the arm still follows "
    "(``smallest=True``: the smallest), by parallel bisection to ``resolution`` (default 1 % of "
    "the range): ``faze4 sweep --find``. Other keywords: the options of ``command``.\n\n"
    "Returns a :class:`Found`."
)
Robot.faze4.__func__.__doc__ = (Robot.faze4.__doc__ or "") + "\n\n" + "\n".join(_doc_lines(_TABLES["run"]))
