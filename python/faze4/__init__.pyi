"""Type stubs of faze4 (written by tools/python/stubs.py from the options the library declares)."""

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
    def __new__(
        cls,
        *,
        robot: str | os.PathLike[str] | None = None,
        xacro_arg: Sequence[str] | None = None,
        package_path: Sequence[str | os.PathLike[str]] | None = None,
        balance_inertia: bool = False,
        tool_link: str | None = None,
        effort: str | Sequence[float | None] | np.ndarray | None = None,
        kp: str | Sequence[float | None] | np.ndarray | None = None,
        kd: str | Sequence[float | None] | np.ndarray | None = None,
        motors: str | os.PathLike[str] | dict[str, Any] | None = None,
        supply_voltage: float | None = None,
        drive: Literal['pd', 'stepper', 'servo'] | None = None,
        microsteps: str | Sequence[float | None] | np.ndarray | None = None,
        driver_bandwidth: float | None = None,
        rotor_damping: str | Sequence[float | None] | np.ndarray | None = None,
        reducer_friction: str | Sequence[float | None] | np.ndarray | None = None,
        servo_rate: float | None = None,
        sizing: bool = False,
        rotor_inertia: str | Sequence[float | None] | np.ndarray | None = None,
        gear_ratio: str | Sequence[float | None] | np.ndarray | None = None,
        max_speed: str | Sequence[float | None] | np.ndarray | None = None,
        no_ff: bool = False,
        ff: Literal['gravity', 'full'] | None = None,
        no_gravity: bool = False,
        payload_kg: float = 0.0,
        dt: float = 0.0002,
        debug: bool = False,
        quiet: bool = True,
        print_period: float | None = None,
        max_saturation_pct: float = 5.0,
        max_error: float = 0.05,
        max_deviation_mm: float = 5.0,
        strict: bool = False,
        trail: str | os.PathLike[str] | None = None,
        summary: str | os.PathLike[str] | None = None,
        record_period: float = 0.02,
        collision_geometry: Literal['mesh', 'hull'] = 'mesh',
        collision_pairs: Literal['all'] | None = None,
        clearance_tolerance: float = 1.0,
        no_collisions: bool = False,
        self_collisions: bool = False,
        friction: float = 1.0,
        view: bool = False,
        port: int = 7000,
        hold: bool = False,
        html: str | os.PathLike[str] | None = None,
        plot: str | os.PathLike[str] | None = None,
        plot_motors: str | os.PathLike[str] | None = None,
    ) -> Robot: ...
    @classmethod
    def faze4(
        cls,
        *,
        robot: str | os.PathLike[str] | None = None,
        xacro_arg: Sequence[str] | None = None,
        package_path: Sequence[str | os.PathLike[str]] | None = None,
        balance_inertia: bool = False,
        tool_link: str | None = None,
        effort: str | Sequence[float | None] | np.ndarray | None = None,
        kp: str | Sequence[float | None] | np.ndarray | None = None,
        kd: str | Sequence[float | None] | np.ndarray | None = None,
        motors: str | os.PathLike[str] | dict[str, Any] | None = None,
        supply_voltage: float | None = None,
        drive: Literal['pd', 'stepper', 'servo'] | None = None,
        microsteps: str | Sequence[float | None] | np.ndarray | None = None,
        driver_bandwidth: float | None = None,
        rotor_damping: str | Sequence[float | None] | np.ndarray | None = None,
        reducer_friction: str | Sequence[float | None] | np.ndarray | None = None,
        servo_rate: float | None = None,
        sizing: bool = False,
        rotor_inertia: str | Sequence[float | None] | np.ndarray | None = None,
        gear_ratio: str | Sequence[float | None] | np.ndarray | None = None,
        max_speed: str | Sequence[float | None] | np.ndarray | None = None,
        no_ff: bool = False,
        ff: Literal['gravity', 'full'] | None = None,
        no_gravity: bool = False,
        payload_kg: float = 0.0,
        dt: float = 0.0002,
        debug: bool = False,
        quiet: bool = True,
        print_period: float | None = None,
        max_saturation_pct: float = 5.0,
        max_error: float = 0.05,
        max_deviation_mm: float = 5.0,
        strict: bool = False,
        trail: str | os.PathLike[str] | None = None,
        summary: str | os.PathLike[str] | None = None,
        record_period: float = 0.02,
        collision_geometry: Literal['mesh', 'hull'] = 'mesh',
        collision_pairs: Literal['all'] | None = None,
        clearance_tolerance: float = 1.0,
        no_collisions: bool = False,
        self_collisions: bool = False,
        friction: float = 1.0,
        view: bool = False,
        port: int = 7000,
        hold: bool = False,
        html: str | os.PathLike[str] | None = None,
        plot: str | os.PathLike[str] | None = None,
        plot_motors: str | os.PathLike[str] | None = None,
    ) -> Robot: ...
    @classmethod
    def from_urdf(
        cls,
        path: str | os.PathLike[str],
        package_path: Sequence[str | os.PathLike[str]] | None = None,
        tool_link: str | None = None,
        *,
        xacro_arg: Sequence[str] | None = None,
        balance_inertia: bool = False,
        effort: str | Sequence[float | None] | np.ndarray | None = None,
        kp: str | Sequence[float | None] | np.ndarray | None = None,
        kd: str | Sequence[float | None] | np.ndarray | None = None,
        motors: str | os.PathLike[str] | dict[str, Any] | None = None,
        supply_voltage: float | None = None,
        drive: Literal['pd', 'stepper', 'servo'] | None = None,
        microsteps: str | Sequence[float | None] | np.ndarray | None = None,
        driver_bandwidth: float | None = None,
        rotor_damping: str | Sequence[float | None] | np.ndarray | None = None,
        reducer_friction: str | Sequence[float | None] | np.ndarray | None = None,
        servo_rate: float | None = None,
        sizing: bool = False,
        rotor_inertia: str | Sequence[float | None] | np.ndarray | None = None,
        gear_ratio: str | Sequence[float | None] | np.ndarray | None = None,
        max_speed: str | Sequence[float | None] | np.ndarray | None = None,
        no_ff: bool = False,
        ff: Literal['gravity', 'full'] | None = None,
        no_gravity: bool = False,
        payload_kg: float = 0.0,
        dt: float = 0.0002,
        debug: bool = False,
        quiet: bool = True,
        print_period: float | None = None,
        max_saturation_pct: float = 5.0,
        max_error: float = 0.05,
        max_deviation_mm: float = 5.0,
        strict: bool = False,
        trail: str | os.PathLike[str] | None = None,
        summary: str | os.PathLike[str] | None = None,
        record_period: float = 0.02,
        collision_geometry: Literal['mesh', 'hull'] = 'mesh',
        collision_pairs: Literal['all'] | None = None,
        clearance_tolerance: float = 1.0,
        no_collisions: bool = False,
        self_collisions: bool = False,
        friction: float = 1.0,
        view: bool = False,
        port: int = 7000,
        hold: bool = False,
        html: str | os.PathLike[str] | None = None,
        plot: str | os.PathLike[str] | None = None,
        plot_motors: str | os.PathLike[str] | None = None,
    ) -> Robot: ...


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


def wave(
    robot: Robot,
    *,
    duration: float = 8.0,
    freq: float = 0.5,
    amp_deg: float = 25.0,
    amp_m: float | None = None,
    center: str | Sequence[float] | None = None,
    xacro_arg: Sequence[str] | None = None,
    package_path: Sequence[str | os.PathLike[str]] | None = None,
    balance_inertia: bool = False,
    tool_link: str | None = None,
    effort: str | Sequence[float | None] | np.ndarray | None = None,
    kp: str | Sequence[float | None] | np.ndarray | None = None,
    kd: str | Sequence[float | None] | np.ndarray | None = None,
    motors: str | os.PathLike[str] | dict[str, Any] | None = None,
    supply_voltage: float | None = None,
    drive: Literal['pd', 'stepper', 'servo'] | None = None,
    microsteps: str | Sequence[float | None] | np.ndarray | None = None,
    driver_bandwidth: float | None = None,
    rotor_damping: str | Sequence[float | None] | np.ndarray | None = None,
    reducer_friction: str | Sequence[float | None] | np.ndarray | None = None,
    servo_rate: float | None = None,
    sizing: bool = False,
    rotor_inertia: str | Sequence[float | None] | np.ndarray | None = None,
    gear_ratio: str | Sequence[float | None] | np.ndarray | None = None,
    max_speed: str | Sequence[float | None] | np.ndarray | None = None,
    no_ff: bool = False,
    ff: Literal['gravity', 'full'] | None = None,
    no_gravity: bool = False,
    payload_kg: float = 0.0,
    dt: float = 0.0002,
    debug: bool = False,
    quiet: bool = True,
    print_period: float | None = None,
    max_saturation_pct: float = 5.0,
    max_error: float = 0.05,
    max_deviation_mm: float = 5.0,
    strict: bool = False,
    trail: str | os.PathLike[str] | None = None,
    summary: str | os.PathLike[str] | None = None,
    record_period: float = 0.02,
    collision_geometry: Literal['mesh', 'hull'] = 'mesh',
    collision_pairs: Literal['all'] | None = None,
    clearance_tolerance: float = 1.0,
    no_collisions: bool = False,
    self_collisions: bool = False,
    friction: float = 1.0,
    view: bool = False,
    port: int = 7000,
    hold: bool = False,
    html: str | os.PathLike[str] | None = None,
    plot: str | os.PathLike[str] | None = None,
    plot_motors: str | os.PathLike[str] | None = None,
) -> Run: ...

def replay(
    robot: Robot,
    q_traj: npt.ArrayLike | str | os.PathLike[str],
    t: npt.ArrayLike | None = None,
    v: npt.ArrayLike | None = None,
    a: npt.ArrayLike | None = None,
    joint_names: Sequence[str] | None = None,
    *,
    traj_period: float = 5.0,
    message: int | None = None,
    topic: str | None = None,
    rename: Sequence[str] | None = None,
    episode: int | None = None,
    lerobot_key: str | None = None,
    units: Literal['deg', 'rad'] | None = None,
    calibration: str | os.PathLike[str] | None = None,
    duration: float | None = None,
    start: str | Sequence[float | None] | np.ndarray | None = None,
    interpolation: Literal['linear', 'cubic', 'quintic'] | None = None,
    xacro_arg: Sequence[str] | None = None,
    package_path: Sequence[str | os.PathLike[str]] | None = None,
    balance_inertia: bool = False,
    tool_link: str | None = None,
    effort: str | Sequence[float | None] | np.ndarray | None = None,
    kp: str | Sequence[float | None] | np.ndarray | None = None,
    kd: str | Sequence[float | None] | np.ndarray | None = None,
    motors: str | os.PathLike[str] | dict[str, Any] | None = None,
    supply_voltage: float | None = None,
    drive: Literal['pd', 'stepper', 'servo'] | None = None,
    microsteps: str | Sequence[float | None] | np.ndarray | None = None,
    driver_bandwidth: float | None = None,
    rotor_damping: str | Sequence[float | None] | np.ndarray | None = None,
    reducer_friction: str | Sequence[float | None] | np.ndarray | None = None,
    servo_rate: float | None = None,
    sizing: bool = False,
    rotor_inertia: str | Sequence[float | None] | np.ndarray | None = None,
    gear_ratio: str | Sequence[float | None] | np.ndarray | None = None,
    max_speed: str | Sequence[float | None] | np.ndarray | None = None,
    no_ff: bool = False,
    ff: Literal['gravity', 'full'] | None = None,
    no_gravity: bool = False,
    payload_kg: float = 0.0,
    dt: float = 0.0002,
    debug: bool = False,
    quiet: bool = True,
    print_period: float | None = None,
    max_saturation_pct: float = 5.0,
    max_error: float = 0.05,
    max_deviation_mm: float = 5.0,
    strict: bool = False,
    trail: str | os.PathLike[str] | None = None,
    summary: str | os.PathLike[str] | None = None,
    record_period: float = 0.02,
    collision_geometry: Literal['mesh', 'hull'] = 'mesh',
    collision_pairs: Literal['all'] | None = None,
    clearance_tolerance: float = 1.0,
    no_collisions: bool = False,
    self_collisions: bool = False,
    friction: float = 1.0,
    view: bool = False,
    port: int = 7000,
    hold: bool = False,
    html: str | os.PathLike[str] | None = None,
    plot: str | os.PathLike[str] | None = None,
    plot_motors: str | os.PathLike[str] | None = None,
) -> Run: ...

def shape(
    robot: Robot,
    shape: Literal['sine', 'circle', 'tri'],
    *,
    shape_points: int = 240,
    duration: float = 12.0,
    save_q: str | os.PathLike[str] | None = None,
    xacro_arg: Sequence[str] | None = None,
    package_path: Sequence[str | os.PathLike[str]] | None = None,
    balance_inertia: bool = False,
    tool_link: str | None = None,
    effort: str | Sequence[float | None] | np.ndarray | None = None,
    kp: str | Sequence[float | None] | np.ndarray | None = None,
    kd: str | Sequence[float | None] | np.ndarray | None = None,
    motors: str | os.PathLike[str] | dict[str, Any] | None = None,
    supply_voltage: float | None = None,
    drive: Literal['pd', 'stepper', 'servo'] | None = None,
    microsteps: str | Sequence[float | None] | np.ndarray | None = None,
    driver_bandwidth: float | None = None,
    rotor_damping: str | Sequence[float | None] | np.ndarray | None = None,
    reducer_friction: str | Sequence[float | None] | np.ndarray | None = None,
    servo_rate: float | None = None,
    sizing: bool = False,
    rotor_inertia: str | Sequence[float | None] | np.ndarray | None = None,
    gear_ratio: str | Sequence[float | None] | np.ndarray | None = None,
    max_speed: str | Sequence[float | None] | np.ndarray | None = None,
    no_ff: bool = False,
    ff: Literal['gravity', 'full'] | None = None,
    no_gravity: bool = False,
    payload_kg: float = 0.0,
    dt: float = 0.0002,
    debug: bool = False,
    quiet: bool = True,
    print_period: float | None = None,
    max_saturation_pct: float = 5.0,
    max_error: float = 0.05,
    max_deviation_mm: float = 5.0,
    strict: bool = False,
    trail: str | os.PathLike[str] | None = None,
    summary: str | os.PathLike[str] | None = None,
    record_period: float = 0.02,
    collision_geometry: Literal['mesh', 'hull'] = 'mesh',
    collision_pairs: Literal['all'] | None = None,
    clearance_tolerance: float = 1.0,
    no_collisions: bool = False,
    self_collisions: bool = False,
    friction: float = 1.0,
    view: bool = False,
    port: int = 7000,
    hold: bool = False,
    html: str | os.PathLike[str] | None = None,
    plot: str | os.PathLike[str] | None = None,
    plot_motors: str | os.PathLike[str] | None = None,
) -> Run: ...

def retime(
    robot: Robot,
    q_path: npt.ArrayLike | str | os.PathLike[str],
    *,
    traj_period: float = 5.0,
    message: int | None = None,
    topic: str | None = None,
    rename: Sequence[str] | None = None,
    episode: int | None = None,
    lerobot_key: str | None = None,
    units: Literal['deg', 'rad'] | None = None,
    calibration: str | os.PathLike[str] | None = None,
    out: str | os.PathLike[str] | None = None,
    grid: int = 200,
    margin: float = 0.3,
    attempts: int = 8,
    force: bool = False,
    no_check: bool = False,
    max_accel: str | Sequence[float | None] | np.ndarray | None = None,
    max_jerk: str | Sequence[float | None] | np.ndarray | None = None,
    start_velocity: str | Sequence[float | None] | np.ndarray | None = None,
    end_velocity: str | Sequence[float | None] | np.ndarray | None = None,
    xacro_arg: Sequence[str] | None = None,
    package_path: Sequence[str | os.PathLike[str]] | None = None,
    balance_inertia: bool = False,
    tool_link: str | None = None,
    effort: str | Sequence[float | None] | np.ndarray | None = None,
    kp: str | Sequence[float | None] | np.ndarray | None = None,
    kd: str | Sequence[float | None] | np.ndarray | None = None,
    motors: str | os.PathLike[str] | dict[str, Any] | None = None,
    supply_voltage: float | None = None,
    drive: Literal['pd', 'stepper', 'servo'] | None = None,
    microsteps: str | Sequence[float | None] | np.ndarray | None = None,
    driver_bandwidth: float | None = None,
    rotor_damping: str | Sequence[float | None] | np.ndarray | None = None,
    reducer_friction: str | Sequence[float | None] | np.ndarray | None = None,
    servo_rate: float | None = None,
    sizing: bool = False,
    rotor_inertia: str | Sequence[float | None] | np.ndarray | None = None,
    gear_ratio: str | Sequence[float | None] | np.ndarray | None = None,
    max_speed: str | Sequence[float | None] | np.ndarray | None = None,
    no_ff: bool = False,
    ff: Literal['gravity', 'full'] | None = None,
    no_gravity: bool = False,
    payload_kg: float = 0.0,
    dt: float = 0.0002,
    debug: bool = False,
    quiet: bool = True,
    print_period: float | None = None,
    max_saturation_pct: float = 5.0,
    max_error: float = 0.05,
    max_deviation_mm: float = 5.0,
    strict: bool = False,
    trail: str | os.PathLike[str] | None = None,
    summary: str | os.PathLike[str] | None = None,
    record_period: float = 0.02,
    collision_geometry: Literal['mesh', 'hull'] = 'mesh',
    collision_pairs: Literal['all'] | None = None,
    clearance_tolerance: float = 1.0,
    no_collisions: bool = False,
    self_collisions: bool = False,
    friction: float = 1.0,
    view: bool = False,
    port: int = 7000,
    hold: bool = False,
    html: str | os.PathLike[str] | None = None,
    plot: str | os.PathLike[str] | None = None,
    plot_motors: str | os.PathLike[str] | None = None,
) -> Retimed: ...

def sweep(
    robot: Robot,
    command: Literal['wave', 'replay', 'shape'],
    vary: dict[str, npt.ArrayLike | str],
    jobs: int = 0,
    own_clearance: bool = False,
    **options: Any,
) -> list[dict[str, Any]]: ...

def find(
    robot: Robot,
    command: Literal['wave', 'replay', 'shape'],
    name: str,
    lo: float,
    hi: float,
    resolution: float | None = None,
    smallest: bool = False,
    jobs: int = 0,
    own_clearance: bool = False,
    **options: Any,
) -> Found: ...
