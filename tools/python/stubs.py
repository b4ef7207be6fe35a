#!/usr/bin/env python3
"""Writes python/faze4/__init__.pyi, the type stubs of the faze4 package, from the options the
installed faze4 reads from the library's declarations (src/config/fields.rs). Run it after an
option is added or changed (python/tests/test_api.py::test_stub_keywords_are_the_binarys_options fails
until it is):

    python tools/python/stubs.py
"""

from __future__ import annotations

import pathlib

import faze4

OUT = pathlib.Path(__file__).resolve().parents[2] / "python" / "faze4" / "__init__.pyi"

# options whose text value also takes a list (joined with commas, as the command line writes it)
TEXT_OR_LIST = {"center": "str | Sequence[float]"}
# options that take more than their command-line kind says
ACCEPTED = {"motors": "str | os.PathLike[str] | dict[str, Any]"}


def annotation(option: faze4.Option) -> str:
    if option.name in TEXT_OR_LIST:
        kind = TEXT_OR_LIST[option.name]
    elif option.name in ACCEPTED:
        kind = ACCEPTED[option.name]
    elif option.kind == "flag":
        return "bool"
    elif option.choices:
        kind = "Literal[%s]" % ", ".join(repr(c) for c in option.choices)
    else:
        kind = {
            "float": "float",
            "int": "int",
            "str": "str",
            "path": "str | os.PathLike[str]",
            "joints": "str | Sequence[float | None] | np.ndarray",
        }[option.kind]
    if option.repeated:
        kind = f"Sequence[{kind}]"
    return kind if faze4._default(option) is not None else f"{kind} | None"


def keywords(command: str, skip: tuple[str, ...] = ()) -> list[str]:
    return [
        f"    {o.name}: {annotation(o)} = {faze4._default(o)!r},"
        for o in faze4.options(command)
        if o.name not in skip
    ]


def function(name: str, head: list[str], command: str, skip: tuple[str, ...], returns: str) -> str:
    return "\n".join([f"def {name}(", *head, "    *,", *keywords(command, skip), f") -> {returns}: ..."])


HEADER = '''"""Type stubs of faze4 (written by tools/python/stubs.py from the options the library declares)."""

import os
from typing import Any, Literal, NamedTuple, Sequence

import numpy as np
import numpy.typing as npt

__version__: str

PYTHON_DEFAULTS: dict[str, Any]

class Error(ValueError): ...

class CannotFollow(Error):
    run: Run | None
    def __init__(self, verdict: str, run: Run | None = None) -> None: ...

class Option(NamedTuple):
    name: str
    long: str
    kind: str
    repeated: bool
    required: bool
    default: str | None
    choices: list[str]
    help: str

def options(command: str) -> list[Option]: ...

Vector = npt.ArrayLike

class Robot:
    @property
    def dof(self) -> int: ...
    @property
    def joint_names(self) -> list[str]: ...
    @property
    def link_names(self) -> list[str]: ...
    @property
    def effort(self) -> npt.NDArray[np.float64]: ...
    @property
    def lower(self) -> npt.NDArray[np.float64]: ...
    @property
    def upper(self) -> npt.NDArray[np.float64]: ...
    def mass_matrix(self, q: Vector) -> npt.NDArray[np.float64]: ...
    def gravity(self, q: Vector) -> npt.NDArray[np.float64]: ...
    def rnea(self, q: Vector, v: Vector, a: Vector) -> npt.NDArray[np.float64]: ...
    def aba(self, q: Vector, v: Vector, tau: Vector) -> npt.NDArray[np.float64]: ...
    def frame_pose(self, q: Vector, link: str) -> npt.NDArray[np.float64]: ...
'''

RUN = '''
class Run:
    summary: dict[str, Any]
    follows: bool
    verdict: str
    verdict_line: str
    reasons: list[str]
    t: npt.NDArray[np.float64]
    q: npt.NDArray[np.float64]
    q_cmd: npt.NDArray[np.float64]
    tool_xyz: npt.NDArray[np.float64]
    warnings: list[str]

class Retimed:
    t: npt.NDArray[np.float64]
    q: npt.NDArray[np.float64]
    qd: npt.NDArray[np.float64]
    qdd: npt.NDArray[np.float64]
    joint_names: list[str]
    duration: float
    own_duration: float | None
    run: Run
    lines: str
    @property
    def speedup(self) -> float | None: ...
    @property
    def follows(self) -> bool: ...
    @property
    def verdict(self) -> str: ...
    @property
    def verdict_line(self) -> str: ...

class Found:
    name: str
    found: Literal['boundary', 'none_follows', 'all_follow']
    value: float | None
    fails_at: float | None
    reason: str
    line: str
    follows: dict[str, Any] | None
    fails: dict[str, Any] | None
    warnings: list[str]
'''


def robot_constructors() -> str:
    run = keywords("run")
    new = ["    def __new__(", "        cls,", "        *,"] + ["    " + k for k in run] + ["    ) -> Robot: ..."]
    faze4_ = ["    @classmethod", "    def faze4(", "        cls,", "        *,"]
    faze4_ += ["    " + k for k in run] + ["    ) -> Robot: ..."]
    urdf_kw = [k for k in keywords("run", ("robot", "package_path", "tool_link"))]
    from_urdf = [
        "    @classmethod",
        "    def from_urdf(",
        "        cls,",
        "        path: str | os.PathLike[str],",
        "        package_path: Sequence[str | os.PathLike[str]] | None = None,",
        "        tool_link: str | None = None,",
        "        *,",
        *["    " + k for k in urdf_kw],
        "    ) -> Robot: ...",
    ]
    return "\n".join(new + faze4_ + from_urdf)


def main() -> None:
    parts = [HEADER + robot_constructors(), RUN]
    # a run's `robot` is the Robot (the robot file is the Robot's own option)
    parts.append(function("wave", ["    robot: Robot,"], "wave", ("robot",), "Run"))
    replay_head = [
        "    robot: Robot,",
        "    q_traj: npt.ArrayLike | str | os.PathLike[str],",
        "    t: npt.ArrayLike | None = None,",
        "    v: npt.ArrayLike | None = None,",
        "    a: npt.ArrayLike | None = None,",
        "    joint_names: Sequence[str] | None = None,",
    ]
    parts.append(function("replay", replay_head, "replay", ("q_traj", "robot"), "Run"))
    parts.append(function("shape", ["    robot: Robot,", "    shape: Literal['sine', 'circle', 'tri'],"], "shape", ("shape", "robot"), "Run"))
    retime_head = ["    robot: Robot,", "    q_path: npt.ArrayLike | str | os.PathLike[str],"]
    parts.append(function("retime", retime_head, "retime", ("q_traj", "robot"), "Retimed"))
    sweep_head = [
        "    robot: Robot,",
        "    command: Literal['wave', 'replay', 'shape'],",
        "    vary: dict[str, npt.ArrayLike | str],",
        "    jobs: int = 0,",
        "    own_clearance: bool = False,",
    ]
    find_head = [
        "    robot: Robot,",
        "    command: Literal['wave', 'replay', 'shape'],",
        "    name: str,",
        "    lo: float,",
        "    hi: float,",
        "    resolution: float | None = None,",
        "    smallest: bool = False,",
        "    jobs: int = 0,",
        "    own_clearance: bool = False,",
    ]
    # a sweep's and a search's keywords: the options of the command they run
    for name, head, returns in (("sweep", sweep_head, "list[dict[str, Any]]"), ("find", find_head, "Found")):
        parts.append("\n".join([f"def {name}(", *head, "    **options: Any,", f") -> {returns}: ..."]))
    OUT.write_text("\n\n".join(parts) + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
