#!/usr/bin/python3
"""Siconos as a benchmark peer: a standalone job runner for the SYSTEM interpreter.

Debian's ``python3-siconos`` (4.4) imports only under ``/usr/bin/python3``, not the project's venv, so
``vibroimpact.benchmarks.peer_siconos`` runs this script in a subprocess: a JSON job on stdin, a JSON result on
stdout.  It imports only siconos, numpy, json, math, time and sys (no vibroimpact).  Install Siconos
with ``tools/install_siconos.sh``.

Model (non-dimensional): between impacts ``Z'' = cos(pi t + theta) + gbar``; walls at ``Z = +d/2``
("bottom", wall +1, reached with Zdot > 0) and ``Z = -d/2`` ("top", wall -1, reached with Zdot < 0);
Newton restitution ``Zdot+ = -r Zdot-``.  In Siconos: one 1-DOF ``LagrangianLinearTIDS`` (mass 1, no
stiffness or damping) and two ``Interaction``s, each a ``LagrangianLinearTIR`` gap ``y = C q + e``
(bottom ``d/2 - Z``, top ``Z + d/2``) with ``NewtonImpactNSL(r)``.  The time-dependent forcing is the
external force ``fExt(t)``, Siconos evaluating it whenever it computes the forces, in one of two ways:

* ``"plugin": "/path/to/lib.so"`` in the job: Siconos' own plugin mechanism
  (``setComputeFExtFunction(path, "vi_fext")``) with the C function of ``siconos_force.c (beside this script)``
  (compiled by the caller), ``theta`` and ``gbar`` passed in the DS's parameter vector ``z``;
* otherwise a Python override of ``computeFExt(time)`` (SWIG director).  Same results to the last
  bit, but the director routes every force evaluation through Python (slower per impact).

Methods (``job["method"]``):

* ``{"method": "event-driven", "tol": 1e-10}``: ``EventDriven`` simulation with ``LsodarOSI`` and the
  two LCPs (impact and acceleration level).  LSODAR's ``rtol = atol = tol`` (``setTol(1, tol, tol)``;
  without ``tol`` Siconos' defaults, rtol = 10 eps, atol = 100 eps); the gaps are LSODAR's root
  functions, so an impact is a non-smooth event located by LSODAR's root finder.  Recorded at each
  non-smooth event whose pre-impact velocity (Siconos' velocity memory) moves towards the wall in
  contact and differs from the post-impact velocity: time = the event time, wall = the side of the
  ball, Zdot- = the pre-impact velocity.  ``"h_output"`` (default 0.5) is the step of Siconos' time
  discretisation, i.e. of its time events (output points), not an integration step.
* ``{"method": "moreau-jean", "h": 1e-4}``: ``TimeStepping`` with ``MoreauJeanOSI(theta=0.5)`` and an
  ``LCP`` (default solver, Lemke) at the velocity level.  Impacts are not located inside a step: a
  step whose impulse ``p(1)`` on the ball is nonzero (|p| > ``impulse_tol``, default 1e-14), follows
  a step without impulse on that wall and starts moving towards it starts an impact; its time is the
  END time ``t_{k+1}`` of that step (the time at which the impulse acts on the velocity in the
  scheme), the wall is the sign of the impulse (negative: bottom), Zdot- is the velocity at the start
  of the step ``v_k`` (the velocity the discrete Newton law restitutes).  Consecutive steps with
  impulse on the same wall (a contact kept over several steps, sticking) count as one impact, and a
  contact that resumes without approach (resting) as none.  The reported time is thus up to one step
  ``h`` late, besides the scheme's own O(h) error.

Jobs:

* ``{"kind": "flights", "flights": [{"theta", "z0", "u", "d", "gbar"}, ...], "horizon": 50, ...}``:
  each flight from ``(z0, u)`` at forcing phase ``theta`` (``Z'' = cos(theta + pi tau) + gbar``) until
  its first impact; returns ``{"flights": [{"tau", "wall", "v", "status", "seconds",
  "setup_seconds", "steps", "force"}]}`` with ``(null, 0, null)`` when no impact before ``horizon``
  (restitution ``"r"``, default 0.5: r = 0 makes the event-driven scheme throw at the impact).
* ``{"kind": "run", "d", "gbar", "r", "phi", "v0", "n", "t_end" (or null), "max_seconds", ...}``: a
  run from a bottom impact at phase ``phi`` with pre-impact velocity ``v0`` (``Z = d/2``,
  ``Zdot = -r v0``, ``t = 0``) until ``n`` impacts or ``t_end``; returns ``{"t", "wall", "v",
  "status", "seconds", "setup_seconds", "steps", "force"}``.  ``status``: "ok"; "stalled"
  (``max_seconds`` of the simulation loop used up, checked after every Siconos step or event); "no
  impact" (none within ``horizon`` (default 50) of the last impact, when ``t_end`` is null);
  "crashed: <message>" (any exception, with the impacts found before it).

Output: one line ``SICONOS_PEER_RESULT <json>`` on stdout (Siconos' C++ code may print to stdout
too: the caller looks for that marker).  ``seconds`` is the wall-clock time of the simulation loop
only; ``setup_seconds`` that of building the model and the simulation (including ``initialize``).
Usage: ``echo '{"kind": "version"}' | /usr/bin/python3 src/vibroimpact/_siconos/siconos_peer.py``.
"""

import json
import math
import sys
import time

MARKER = "SICONOS_PEER_RESULT "

try:
    import numpy as np
    import siconos
    import siconos.kernel as sk
except Exception as err:  # reported by the "version" job and every other job
    sk = None
    IMPORT_ERROR = f"{type(err).__name__}: {err}"
else:
    IMPORT_ERROR = None


def _ball_class():
    class ForcedBall(sk.LagrangianLinearTIDS):
        """Unit mass; external force ``cos(pi t + theta) + gbar`` via a Python override (director)."""

        def computeFExt(self, time):
            self._fext[0] = math.cos(math.pi * time + self._theta) + self._gbar

    return ForcedBall


def build(d, gbar, r, theta, z0, u, t_final, setting):
    """The Siconos model and simulation of the ball from ``(z0, u)`` at phase ``theta``, t = 0."""
    q0, v0, mass = np.array([float(z0)]), np.array([float(u)]), np.array([[1.0]])
    if setting.get("plugin"):  # compiled C plugin (siconos_force.c (beside this script)), parameters in z
        ball = sk.LagrangianLinearTIDS(q0, v0, mass)
        ball.setzPtr(np.array([float(theta), float(gbar)]))
        ball.setComputeFExtFunction(str(setting["plugin"]), "vi_fext")
    else:  # Python override of computeFExt
        ball = _ball_class()(q0, v0, mass)
        ball._theta, ball._gbar = float(theta), float(gbar)
        ball.setFExtPtr(np.zeros(1))
        ball._fext = ball.fExt()  # a view on Siconos' own vector
    ball.computeFExt(0.0)
    nsds = sk.NonSmoothDynamicalSystem(0.0, float(t_final))
    nsds.insertDynamicalSystem(ball)
    inters = []
    for sign in (-1.0, 1.0):  # bottom: y = d/2 - Z; top: y = Z + d/2
        rel = sk.LagrangianLinearTIR(np.array([[sign]]), np.array([0.5 * d]))
        inter = sk.Interaction(sk.NewtonImpactNSL(float(r)), rel)
        nsds.link(inter, ball)
        inters.append(inter)
    method = setting["method"]
    if method == "event-driven":
        td = sk.TimeDiscretisation(0.0, float(setting.get("h_output", 0.5)))
        sim = sk.EventDriven(nsds, td)
        osi = sk.LsodarOSI()
        if setting.get("tol") is not None:
            tol = float(setting["tol"])
            osi.setTol(1, tol, tol)  # itol = 1: scalar rtol and atol
        sim.insertIntegrator(osi)
        sim.insertNonSmoothProblem(sk.LCP(), sk.SICONOS_OSNSP_ED_IMPACT)
        sim.insertNonSmoothProblem(sk.LCP(), sk.SICONOS_OSNSP_ED_SMOOTH_ACC)
    elif method == "moreau-jean":
        td = sk.TimeDiscretisation(0.0, float(setting["h"]))
        sim = sk.TimeStepping(nsds, td)
        osi = sk.MoreauJeanOSI(0.5)
        sim.insertIntegrator(osi)
        sim.insertNonSmoothProblem(sk.LCP())
    else:
        raise ValueError(f"unknown method {method!r} (event-driven or moreau-jean)")
    sim.initialize()
    return dict(ball=ball, nsds=nsds, inters=inters, sim=sim, osi=osi, td=td)


class Recorder:
    """Collects impacts ``(t, wall, Zdot-)``; ``done()`` says when to stop."""

    def __init__(self, n, t_end, horizon, max_seconds):
        self.n, self.t_end, self.horizon, self.max_seconds = n, t_end, horizon, max_seconds
        self.t, self.wall, self.v = [], [], []
        self.status = "ok"
        self.steps = 0
        self.stage = "start"  # the Siconos call under way, for the crash message
        self.start = time.perf_counter()

    def add(self, t, wall, v):
        if self.t_end is not None and t > self.t_end:
            return
        self.t.append(float(t))
        self.wall.append(int(wall))
        self.v.append(float(v))

    def done(self, now):
        """True when the loop must stop at simulation time ``now`` (sets the status)."""
        if len(self.t) >= self.n:
            return True
        if self.t_end is not None and now >= self.t_end:
            return True
        last = self.t[-1] if self.t else 0.0
        if self.t_end is None and now - last > self.horizon:
            self.status = "no impact"
            return True
        if time.perf_counter() - self.start > self.max_seconds:
            self.status = "stalled"
            return True
        return False


def loop_event_driven(m, rec):
    sim, ball = m["sim"], m["ball"]
    em = sim.eventsManager()
    qmem, vmem = ball.qMemory(), ball.velocityMemory()
    vnow = ball.velocity()
    ns_type = sk.NS_EVENT
    while sim.hasNextEvent():
        rec.stage = "advanceToEvent"
        sim.advanceToEvent()
        nonsmooth = em.nextEvent().getType() == ns_type
        rec.stage = "processEvents (non-smooth event)" if nonsmooth else "processEvents"
        sim.processEvents()
        rec.steps += 1
        now = sim.startingTime()
        if nonsmooth:
            z_pre = qmem.getSiconosVector(1)[0]
            v_pre = vmem.getSiconosVector(1)[0]
            wall = 1 if z_pre > 0 else -1
            if wall * v_pre > 0 and vnow[0] != v_pre:  # moving into the wall, and a jump
                rec.add(now, wall, v_pre)
        if rec.done(now):
            return
    if rec.t_end is None and len(rec.t) < rec.n:
        rec.status = "no impact"


def loop_moreau_jean(m, rec, impulse_tol):
    sim, ball = m["sim"], m["ball"]
    vel = ball.velocity()
    p1 = ball.p(1)
    prev = 0  # wall of the impulse of the previous step (0: none)
    while sim.hasNextEvent():
        v_start = vel[0]
        rec.stage = "computeOneStep"
        sim.computeOneStep()
        rec.steps += 1
        now = sim.nextTime()
        p = p1[0]
        wall = 0 if abs(p) <= impulse_tol else (1 if p < 0 else -1)
        if wall != 0 and wall != prev:
            if wall * v_start > 0:  # an impact; else a contact resumed without approach (resting)
                rec.add(now, wall, v_start)
        prev = wall
        sim.nextStep()
        if rec.done(now):
            return
    if rec.t_end is None and len(rec.t) < rec.n:
        rec.status = "no impact"


def simulate(d, gbar, r, theta, z0, u, n, t_end, horizon, max_seconds, setting):
    """Build and run; returns the result dict of a run (impacts, status, timings)."""
    # Siconos ends at its last time event <= its final time: run past t_end, cut in the loop
    t_final = t_end + 1.0 if t_end is not None else 1e6
    start = time.perf_counter()
    res = dict(t=[], wall=[], v=[], status="ok", seconds=0.0, setup_seconds=0.0, steps=0,
               force="plugin" if setting.get("plugin") else "python")
    try:
        m = build(d, gbar, r, theta, z0, u, t_final, setting)
    except Exception as err:
        res.update(status=f"crashed: setup: {type(err).__name__}: {err}",
                   setup_seconds=time.perf_counter() - start)
        return res
    res["setup_seconds"] = time.perf_counter() - start
    rec = Recorder(n, t_end, horizon, max_seconds)
    try:
        if setting["method"] == "event-driven":
            loop_event_driven(m, rec)
        else:
            loop_moreau_jean(m, rec, float(setting.get("impulse_tol", 1e-14)))
    except Exception as err:  # Siconos' own exceptions reach Python as "Exception: std::exception"
        try:
            at = f" at t = {m['sim'].startingTime():.9g}"
        except Exception:
            at = ""
        rec.status = f"crashed: {type(err).__name__}: {err} (in {rec.stage}{at})"
    res.update(t=rec.t, wall=rec.wall, v=rec.v, status=rec.status, seconds=time.perf_counter() - rec.start,
               steps=rec.steps)
    return res


def _setting(job):
    keys = ("method", "tol", "h", "h_output", "impulse_tol", "plugin")
    return {k: job[k] for k in keys if k in job}


def job_flights(job):
    setting = _setting(job)
    horizon = float(job.get("horizon", 50.0))
    max_seconds = float(job.get("max_seconds", 60.0))
    # the restitution does not change the first impact, but r = 0 (a plastic impact) makes Siconos'
    # event-driven processing of that impact throw before it can be recorded
    restitution = float(job.get("r", 0.5))
    out = []
    for f in job["flights"]:
        res = simulate(f["d"], f["gbar"], restitution, f["theta"], f["z0"], f["u"], 1, horizon, horizon,
                       max_seconds, setting)
        hit = bool(res["t"])
        status = res["status"] if (hit or res["status"] != "ok") else "no impact"
        out.append(dict(tau=res["t"][0] if hit else None, wall=res["wall"][0] if hit else 0,
                        v=res["v"][0] if hit else None, status=status, seconds=res["seconds"],
                        setup_seconds=res["setup_seconds"], steps=res["steps"], force=res["force"]))
    return dict(flights=out)


def job_run(job):
    setting = _setting(job)
    d, r = float(job["d"]), float(job["r"])
    t_end = job.get("t_end")
    return simulate(d, float(job["gbar"]), r, float(job["phi"]), 0.5 * d, -r * float(job["v0"]),
                    int(job["n"]), None if t_end is None else float(t_end), float(job.get("horizon", 50.0)),
                    float(job.get("max_seconds", 60.0)), setting)


def main():
    try:
        job = json.loads(sys.stdin.read() or "{}")
        kind = job.get("kind", "version")
        if IMPORT_ERROR is not None:
            res = dict(error=f"siconos not importable: {IMPORT_ERROR}")
        elif kind == "version":
            res = dict(version=str(getattr(siconos, "version", "unknown")), python=sys.version.split()[0],
                       numpy=np.__version__)
        elif kind == "flights":
            res = job_flights(job)
        elif kind == "run":
            res = job_run(job)
        else:
            res = dict(error=f"unknown job kind {kind!r}")
    except Exception as err:
        res = dict(error=f"{type(err).__name__}: {err}")
    sys.stdout.write("\n" + MARKER + json.dumps(res) + "\n")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
