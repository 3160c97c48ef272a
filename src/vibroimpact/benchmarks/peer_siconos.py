"""Siconos (nonsmooth dynamics library) as a benchmark peer, run outside the venv.

Debian's ``python3-siconos`` (4.4; install with ``tools/install_siconos.sh``) imports only under the
system interpreter, so each call here runs ``_siconos/siconos_peer.py`` (in the package) under ``/usr/bin/python3``
(overridable by the environment variable ``VIBROIMPACT_SICONOS_PYTHON``) with a JSON job on stdin.
That script documents the model and the two methods:

* ``method="event-driven"`` (``tol=...``): ``EventDriven`` + ``LsodarOSI`` with rtol = atol = tol
  (without ``tol``: Siconos' defaults, rtol = 10 eps, atol = 100 eps); an impact is a non-smooth event
  located by LSODAR's root finder on the gaps.
* ``method="moreau-jean"`` (``h=...``): ``TimeStepping`` + ``MoreauJeanOSI(0.5)`` + ``LCP``; an impact is
  reported at the END time of the first step with a nonzero impulse on a wall (so within one step
  ``h`` of the true time), with the velocity at the start of that step as Zdot-.

The forcing (``force=``): ``"plugin"``, Siconos' plugin mechanism with the C function of
``_siconos/siconos_force.c``, compiled here once with the system C compiler (``$CC`` or ``cc``) into
``~/.cache/vibroimpact/``; ``"python"``, a Python override of ``computeFExt`` (slower per
impact, the same numbers to the last bit); ``"auto"`` (default), the plugin when it compiles, else Python.
``SiconosRun.force`` / ``FlightResult.force`` say which was used.

Runs use one thread (``OMP_NUM_THREADS`` / ``OPENBLAS_NUM_THREADS`` default to 1 in the child).
``Run.seconds`` is the wall-clock time of the simulation loop only; :class:`SiconosRun` adds the model
construction time (``setup_seconds``), the number of Siconos steps or events (``steps``) and ``force``.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np

from .._code_version import cache_home
from ..dynamics import impact as law
from ..dynamics.params import Params
from .methods import CRASHED, STALLED, Run

__all__ = ["METHODS", "FlightResult", "SiconosPeerError", "SiconosRun", "SiconosUnavailable", "available",
           "run_siconos", "siconos_flights", "unavailable_reason", "version"]

#: Method names understood by the peer script, and the settings each accepts (besides ``force``).
METHODS = {"event-driven": ("tol", "h_output"), "moreau-jean": ("h", "impulse_tol")}
FORCES = ("auto", "plugin", "python")
ENV_PYTHON = "VIBROIMPACT_SICONOS_PYTHON"
DEFAULT_PYTHON = "/usr/bin/python3"
NOT_INSTALLED = "python3-siconos not installed (tools/install_siconos.sh)"
MARKER = "SICONOS_PEER_RESULT "
#: the peer script and the forcing plugin's C source ship with the package (run, not imported, here)
PEER_DIR = Path(__file__).resolve().with_name("_siconos")
SCRIPT = PEER_DIR / "siconos_peer.py"
PLUGIN_SOURCE = PEER_DIR / "siconos_force.c"

_probe_cache: dict[str, tuple[bool, str]] = {}
_plugin_cache: dict[str, tuple[str | None, str]] = {}


class SiconosUnavailable(RuntimeError):
    """Siconos cannot be imported by the system interpreter (or the peer script is missing)."""


class SiconosPeerError(RuntimeError):
    """The peer process failed (non-zero exit, signal, or no result line)."""


@dataclass
class SiconosRun(Run):
    setup_seconds: float = 0.0
    steps: int = 0
    force: str = ""


class FlightResult(NamedTuple):
    tau: float  #: flight time to the first impact; inf when none within the horizon
    wall: int  #: +1 bottom, -1 top, 0 none
    v: float  #: pre-impact velocity Zdot-; nan when none
    status: str
    seconds: float
    setup_seconds: float
    force: str


def _python() -> str:
    return os.environ.get(ENV_PYTHON, DEFAULT_PYTHON)


def _probe() -> tuple[bool, str]:
    """(importable, reason) for the current interpreter path, cached per path."""
    py = _python()
    if py not in _probe_cache:
        try:
            out = subprocess.run([py, "-c", "import siconos.kernel"], capture_output=True, text=True,
                                 timeout=120)
            ok = out.returncode == 0
            detail = (out.stderr.strip().splitlines() or [f"exit {out.returncode}"])[-1]
        except (OSError, subprocess.SubprocessError) as err:
            ok, detail = False, f"{type(err).__name__}: {err}"
        if not ok:
            _probe_cache[py] = (False, f"{NOT_INSTALLED}: {py}: {detail}")
        elif not SCRIPT.is_file():
            _probe_cache[py] = (False, f"peer script {SCRIPT} not found (a broken installation)")
        else:
            _probe_cache[py] = (True, "")
    return _probe_cache[py]


def available() -> bool:
    """True when ``<system python> -c "import siconos.kernel"`` succeeds (cached per interpreter)."""
    return _probe()[0]


def unavailable_reason() -> str:
    """Why :func:`available` is False ("" when it is True)."""
    return _probe()[1]


def _require():
    ok, reason = _probe()
    if not ok:
        raise SiconosUnavailable(reason)


def plugin_path() -> tuple[str | None, str]:
    """(path of the compiled forcing plugin, "") or (None, why not); compiled once, cached on disk."""
    cc = os.environ.get("CC", "cc")
    if cc in _plugin_cache:
        return _plugin_cache[cc]
    try:
        src = PLUGIN_SOURCE.read_bytes()
        tag = hashlib.sha256(src + cc.encode()).hexdigest()[:12]
        cache = cache_home()
        out = cache / f"siconos_force-{tag}.so"
        if not out.is_file():
            if shutil.which(cc) is None:
                raise FileNotFoundError(f"no C compiler {cc!r}")
            cache.mkdir(parents=True, exist_ok=True)
            tmp = cache / f"siconos_force-{tag}.{os.getpid()}.so"
            subprocess.run([cc, "-O2", "-shared", "-fPIC", "-o", str(tmp), str(PLUGIN_SOURCE), "-lm"],
                           capture_output=True, text=True, timeout=120, check=True)
            os.replace(tmp, out)
        _plugin_cache[cc] = (str(out), "")
    except (OSError, subprocess.SubprocessError) as err:
        detail = getattr(err, "stderr", "") or ""
        _plugin_cache[cc] = (None, f"{type(err).__name__}: {err} {detail}".strip())
    return _plugin_cache[cc]


def _call(job: dict, timeout: float) -> dict:
    """Run the peer script on ``job``; the parsed result, or SiconosPeerError / TimeoutExpired.  Refuses
    (ValueError) when the package's impact law is not the constant restitution Siconos' ``NewtonImpactNSL``
    applies (:data:`~vibroimpact.dynamics.impact.CONSTANT_RESTITUTION`): the peer would compare another law."""
    if not law.CONSTANT_RESTITUTION:
        raise ValueError("the Siconos peer applies a constant restitution (NewtonImpactNSL), and the impact "
                         "law's restitution is not constant (vibroimpact.dynamics.impact.CONSTANT_RESTITUTION)")
    _require()
    env = dict(os.environ)
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        env.setdefault(var, "1")
    out = subprocess.run([_python(), str(SCRIPT)], input=json.dumps(job), capture_output=True, text=True,
                         timeout=timeout, env=env)
    lines = [ln for ln in out.stdout.splitlines() if MARKER in ln]
    if out.returncode != 0 or not lines:
        why = f"signal {-out.returncode}" if out.returncode < 0 else f"exit {out.returncode}"
        tail = " | ".join((out.stderr.strip() or out.stdout.strip()).splitlines()[-3:])
        raise SiconosPeerError(f"siconos peer failed ({why}): {tail}")
    res = json.loads(lines[-1].split(MARKER, 1)[1])
    if "error" in res:
        raise SiconosPeerError(f"siconos peer: {res['error']}")
    return res


def version() -> str:
    """The Debian package version of python3-siconos (e.g. '4.4.0+dfsg-2'), else the module's own.

    (The Debian 4.4 build's ``siconos.version`` says '4.5.0', the tree it was cut from.)
    """
    _require()
    try:
        out = subprocess.run(["dpkg-query", "-W", "-f=${Version}", "python3-siconos"], capture_output=True,
                             text=True, timeout=30)
        if out.returncode == 0 and out.stdout.strip():
            return out.stdout.strip()
    except (OSError, subprocess.SubprocessError):
        pass
    return _call({"kind": "version"}, timeout=120)["version"]


def _setting(method: str, force: str, setting: dict) -> dict:
    if method not in METHODS:
        raise ValueError(f"method {method!r}: allowed {sorted(METHODS)}")
    bad = set(setting) - set(METHODS[method])
    if bad:
        raise ValueError(f"method {method!r} takes {METHODS[method]} and force, not {sorted(bad)}")
    if method == "moreau-jean" and not setting.get("h", 0) > 0:
        raise ValueError("moreau-jean needs a step h > 0")
    if force not in FORCES:
        raise ValueError(f"force {force!r}: allowed {FORCES}")
    job = dict(method=method, **{k: float(v) for k, v in setting.items() if v is not None})
    if force != "python":
        path, why = plugin_path()
        if path is None and force == "plugin":
            raise SiconosPeerError(f"forcing plugin {PLUGIN_SOURCE.name} could not be built: {why}")
        if path is not None:
            job["plugin"] = path
    return job


def siconos_flights(flights, method: str, *, horizon=50.0, max_seconds=60.0, force="auto",
                    **setting) -> list[FlightResult]:
    """First impact of each flight by Siconos.

    ``flights``: mappings with keys ``theta, z0, u, d, gbar`` or 5-sequences in that order (``theta``
    the forcing phase at the flight start: ``Z'' = cos(theta + pi tau) + gbar``).  Returns one
    :class:`FlightResult` per flight, ``(inf, 0, nan)`` when no impact within ``horizon``.  Raises
    :class:`SiconosUnavailable` without Siconos, :class:`SiconosPeerError` if the peer process dies.
    """
    keys = ("theta", "z0", "u", "d", "gbar")
    fl = [{k: float(f[k]) for k in keys} if isinstance(f, dict)
          else dict(zip(keys, map(float, f), strict=True)) for f in flights]
    job = dict(kind="flights", flights=fl, horizon=float(horizon), max_seconds=float(max_seconds),
               **_setting(method, force, setting))
    res = _call(job, timeout=len(fl) * (max_seconds + 5.0) + 120.0)
    return [FlightResult(math.inf if f["tau"] is None else f["tau"], int(f["wall"]),
                         math.nan if f["v"] is None else f["v"], f["status"], f["seconds"],
                         f["setup_seconds"], f["force"])
            for f in res["flights"]]


def run_siconos(p: Params, phi, v0, n, *, method: str, t_end=math.inf, max_seconds=60.0, force="auto",
                **setting) -> SiconosRun:
    """A run from a bottom impact at phase ``phi`` with pre-impact velocity ``v0`` by Siconos.

    Same contract as the runners of :mod:`vibroimpact.benchmarks.methods`: the first ``n`` impacts after the
    start (or those before ``t_end``), status "ok" / "stalled" / "no impact" / "crashed: <message>".
    A peer process that dies (e.g. an assertion in Siconos) gives "crashed: ..." with no impacts; one
    that outlives ``max_seconds`` + 120 s is killed and gives "stalled".  Raises
    :class:`SiconosUnavailable` without Siconos.
    """
    job = dict(kind="run", d=p.d, gbar=p.gbar, r=p.r, phi=float(phi), v0=float(v0), n=int(n),
               t_end=None if math.isinf(t_end) else float(t_end), max_seconds=float(max_seconds),
               **_setting(method, force, setting))
    empty = (np.zeros(0), np.zeros(0, dtype=int), np.zeros(0))
    try:
        res = _call(job, timeout=max_seconds + 120.0)
    except subprocess.TimeoutExpired:
        return SiconosRun(*empty, STALLED, float(max_seconds))
    except SiconosPeerError as err:
        return SiconosRun(*empty, f"{CRASHED}: {err}", math.nan)
    t, wall, v = (np.array(res[k], dtype=dt) for k, dt in (("t", float), ("wall", int), ("v", float)))
    return SiconosRun(t, wall, v, res["status"], res["seconds"], res["setup_seconds"], res["steps"],
                      res["force"])
