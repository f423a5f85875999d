"""Type stubs of safereach's Python package."""
import os

from typing import Any, Optional, Sequence, Union, overload

import numpy as np
import numpy.typing as npt

class InputError(ValueError):
    """A problem, key, value or certificate text that cannot be read."""

class CertificateError(ValueError):
    """A certificate that check rejects, or that a monitor cannot use."""

class AnalysisError(RuntimeError):
    """An analysis that could not be completed (a budget, the solver)."""

class Problem:
    """A verification problem, scene or planar problem (TOML), with --set-style overrides."""
    def __init__(self, text: str, origin: str = "<string>") -> None: ...
    @staticmethod
    def from_file(path: str) -> "Problem": ...
    @staticmethod
    def from_json(json: str, origin: str = "<dict>") -> "Problem": ...
    def set(self, key: str, value: Union[bool, int, float, str, list]) -> None: ...
    @property
    def name(self) -> str: ...
    @property
    def is_scene(self) -> bool: ...
    @property
    def is_planar(self) -> bool: ...
    def to_json(self) -> str: ...

class Certificate:
    """A verdict with its proof, as certify --out writes it."""
    @staticmethod
    def from_json(text: str) -> "Certificate": ...
    @property
    def verdict(self) -> str: ...
    @property
    def min_separation(self) -> Optional[float]: ...
    @property
    def lower_bound(self) -> Optional[float]: ...
    @property
    def premises(self) -> list[dict[str, Any]]: ...
    @property
    def witness(self) -> Optional[dict[str, Any]]: ...
    def to_dict(self) -> dict[str, Any]: ...
    def to_json(self) -> str: ...

class Monitor:
    """The runtime monitor for a certified certificate."""
    def __init__(self, certificate: Certificate) -> None: ...
    def observe(
        self,
        t: float,
        robot_x: float,
        robot_v: float,
        obstacle_x: float,
        obstacle_v: Optional[float] = None,
        obstacle_t: Optional[float] = None,
        obstacle_id: int = 0,
        robot_mode: Optional[str] = None,
    ) -> tuple[str, list[dict[str, Any]]]: ...
    def observe_many(
        self,
        t: npt.NDArray[np.float64],
        robot_x: npt.NDArray[np.float64],
        robot_v: npt.NDArray[np.float64],
        obstacle_x: npt.NDArray[np.float64],
        obstacle_v: Optional[npt.NDArray[np.float64]] = None,
        obstacle_id: Optional[npt.NDArray[np.uint32]] = None,
    ) -> tuple[str, list[tuple[int, dict[str, Any]]]]: ...
    def observe_bag(
        self,
        path: Union[str, os.PathLike[str]],
        robot_topic: str = "/odom",
        obstacle_topics: Optional[list[str]] = None,
        mode_topic: Optional[str] = None,
        infer_mode: bool = False,
        lane_axis: Optional[tuple[float, float, float]] = None,
        ground_truth: bool = False,
        obstacle_speed: str = "twist",
    ) -> tuple[str, list[tuple[int, dict[str, Any]]]]:
        """Checks a ROS 2 bag (MCAP): (verdict, [(message number, event)])."""
        ...
    @property
    def verdict(self) -> str: ...
    def summary(self) -> dict[str, Any]: ...

class PlanarMonitor:
    """The runtime monitor for a certified planar certificate (obstacles matched by name)."""
    def __init__(self, certificate: Certificate) -> None: ...
    def observe(
        self,
        t: float,
        robot_x: float,
        robot_y: float,
        robot_v: float,
        obstacle: Optional[str] = None,
        obstacle_x: float = 0.0,
        obstacle_y: float = 0.0,
        obstacle_vx: Optional[float] = None,
        obstacle_vy: Optional[float] = None,
        robot_mode: Optional[str] = None,
    ) -> tuple[str, list[dict[str, Any]]]: ...
    @property
    def verdict(self) -> str: ...
    def summary(self) -> dict[str, Any]: ...

class RegionMap:
    """A certified map of a box of parameters (safereach region)."""
    @staticmethod
    def from_json(text: str) -> "RegionMap": ...
    @property
    def leaves(self) -> list[dict[str, Any]]: ...
    @property
    def coverage(self) -> dict[str, float]: ...
    def check(self) -> bool: ...
    def to_json(self) -> str: ...

def region(
    problem: Problem,
    ranges: dict[str, tuple[float, float]],
    depth: Optional[int] = None,  # 14; 8 for a planar problem
    min_width: float = 0.0,
) -> RegionMap: ...
def certify(problem: Problem) -> Certificate: ...
def check(certificate: Certificate) -> str: ...
@overload
def safe_radius(problem: Problem) -> Optional[float]: ...
@overload
def safe_radius(problem: Problem, speeds: Sequence[float]) -> list[Optional[float]]: ...
def max_speed(problem: Problem) -> Optional[float]: ...
def problem_from_dict(data: dict[str, Any], origin: str = "<dict>") -> Problem: ...
