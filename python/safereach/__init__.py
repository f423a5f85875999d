"""safereach: certify or refute passive safety of a mobile robot, with exact certificates and a
runtime monitor.

Every answer comes from the safereach library (Rust): a certificate returned by ``certify``
has passed the exact ``check`` (rational arithmetic, no solver), and a ``Monitor`` accepts only
a certificate that checks as ``certified``. Errors are exceptions carrying the command line's
messages: ``InputError`` (a problem, key or value that cannot be read), ``CertificateError``
(a certificate that does not check, or cannot be monitored) and ``AnalysisError``.
"""

import json as _json

from ._safereach import (
    AnalysisError,
    Certificate,
    CertificateError,
    InputError,
    Monitor,
    PlanarMonitor,
    Problem,
    RegionMap,
    certify,
    check,
    max_speed,
    region,
    safe_radius,
)

__all__ = [
    "AnalysisError",
    "Certificate",
    "CertificateError",
    "InputError",
    "Monitor",
    "PlanarMonitor",
    "Problem",
    "certify",
    "check",
    "max_speed",
    "problem_from_dict",
    "RegionMap",
    "region",
    "safe_radius",
]


def problem_from_dict(data, origin="<dict>"):
    """A problem from a dict with the TOML file's keys (nested tables as dicts)."""
    return Problem.from_json(_json.dumps(data), origin)
