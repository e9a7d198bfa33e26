"""Chart switching: integrate in whichever set of generalized coordinates is regular along the motion.

A :class:`Chart` is one set of lecture coordinates for the same mechanism (one :class:`System`, one per chart,
each with its own tree for the engines), with a *regularity* (a number that is 0 exactly at the chart's own
singularity, e.g. ``|sin theta|`` for the spherical pendulum (5.81)) and a map to and from a common description
of the state (Cartesian position and velocity of the bob; angles of both legs of the toggle press).
:func:`integrate_charts` integrates in one chart until its regularity falls to ``SWITCH`` (located as an event
by ``solve_ivp``), maps the state to the chart that is most regular there and continues.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import sympy as sp

from harness.hard.common import second_order, solve
from harness.modeling.system import Coordinate, Gravity, Joint, Link, System, WORLD
from harness.scenes.simulate import Dynamics

SWITCH = 0.3   # switch charts where the regularity (|sin| of the polar angle, |cos| of a dead-point angle) < 0.3


@dataclass
class Chart:
    name: str
    system: System
    regularity: object      # q -> float, 0 at the singularity
    to_common: object       # (q, qd) -> common state vector
    from_common: object     # common state -> (q, qd)


def integrate_charts(charts: list, dynamics: dict, start: int, q0, qd0, horizon: float, t_eval, method="DOP853",
                     rtol=1e-12, atol=1e-12, switch=SWITCH, max_switches=1000):
    """Integrate through chart singularities; returns ``(t, common states, switches, nfev, cpu seconds)``.
    ``dynamics[chart.name]`` is the ``q̈ = f(t, q, q̇)`` of that chart (symbolic or an engine)."""
    i, t, y = start, 0.0, np.concatenate([q0, qd0]).astype(float)
    ts, xs, switches, nfev, cpu = [], [], [], 0, 0.0
    while t < horizon - 1e-14:
        chart = charts[i]
        n = len(chart.system.coordinates)

        def event(_, yy, chart=chart):
            return chart.regularity(yy[:n]) - switch
        event.terminal, event.direction = True, -1
        inside = t_eval[(t_eval >= t) & (t_eval <= horizon)]
        sol, seconds = solve(second_order(dynamics[chart.name], n), (t, horizon), y, method, rtol, atol,
                             t_eval=inside, events=event)
        cpu += seconds
        nfev += sol.nfev
        if sol.status == -1:
            raise RuntimeError(f"chart {chart.name}: {sol.message}")
        for tk, yk in zip(sol.t, sol.y.T):
            ts.append(tk)
            xs.append(chart.to_common(yk[:n], yk[n:]))
        if sol.status == 1 and sol.t_events[0].size:
            t = float(sol.t_events[0][-1])
            x = chart.to_common(sol.y_events[0][-1][:n], sol.y_events[0][-1][n:])
            j = max(range(len(charts)), key=lambda k: charts[k].regularity(charts[k].from_common(x)[0]))
            switches.append((t, chart.name, charts[j].name))
            if len(switches) > max_switches:
                raise RuntimeError("too many chart switches")
            q, qd = charts[j].from_common(x)
            i, y = j, np.concatenate([q, qd])
        else:
            break
    order = np.argsort(ts, kind="stable")
    t_arr, x_arr = np.array(ts)[order], np.array(xs)[order]
    keep = np.concatenate([[True], np.diff(t_arr) > 1e-12])   # a sample at an event time appears once
    return t_arr[keep], x_arr[keep], switches, nfev, cpu


# ----------------------------------------------------------------------------- spherical pendulum, Example 5.3
def pendulum_charts(lecture: System, length: float) -> list:
    """Two spherical charts of the spherical pendulum: the lecture's ``(theta, phi)`` with its pole at the
    bottom ``-e_y`` (5.75), and ``(psi, chi)`` with the pole along ``e_z``: ``p = l [cos chi sin psi,
    -cos chi cos psi, -sin chi]`` (joint ``psi`` about ``z``, then ``chi`` about the new ``x``)."""
    l = length

    def p_a(q):
        th, ph = q
        return l * np.array([math.sin(th) * math.cos(ph), -math.cos(th), math.sin(th) * math.sin(ph)])

    def j_a(q):
        th, ph = q
        return l * np.array([[math.cos(th) * math.cos(ph), -math.sin(th) * math.sin(ph)],
                             [math.sin(th), 0.0],
                             [math.cos(th) * math.sin(ph), math.sin(th) * math.cos(ph)]])

    def p_b(q):
        ps, ch = q
        return l * np.array([math.cos(ch) * math.sin(ps), -math.cos(ch) * math.cos(ps), -math.sin(ch)])

    def j_b(q):
        ps, ch = q
        return l * np.array([[math.cos(ch) * math.cos(ps), -math.sin(ch) * math.sin(ps)],
                             [math.cos(ch) * math.sin(ps), math.sin(ch) * math.cos(ps)],
                             [0.0, -math.cos(ch)]])

    def from_a(x):
        p, v = x[:3] / l, x[3:]
        q = np.array([math.acos(max(-1.0, min(1.0, -p[1]))), math.atan2(p[2], p[0])])
        return q, np.linalg.lstsq(j_a(q), v, rcond=None)[0]

    def from_b(x):
        p, v = x[:3] / l, x[3:]
        q = np.array([math.atan2(p[0], -p[1]), math.asin(max(-1.0, min(1.0, -p[2])))])
        return q, np.linalg.lstsq(j_b(q), v, rcond=None)[0]

    return [Chart("theta_phi", lecture, lambda q: abs(math.sin(q[0])),
                  lambda q, qd: np.concatenate([p_a(q), j_a(q) @ qd]), from_a),
            Chart("psi_chi", pendulum_chart_b(lecture), lambda q: abs(math.cos(q[1])),
                  lambda q, qd: np.concatenate([p_b(q), j_b(q) @ qd]), from_b)]


def pendulum_chart_b(lecture: System) -> System:
    """The spherical pendulum in the chart ``(psi, chi)`` (its pole along ``e_z``), same parameters and bob."""
    m, l, g = (lecture.parameter(n) for n in ("m", "l", "g"))
    return System(
        name="spherical_pendulum_chart_psi_chi",
        title="Spherical pendulum, second spherical chart (pole along e_z)",
        lecture="Example 5.3 in the chart (psi, chi)",
        parameters=(m, l, g),
        coordinates=(Coordinate("psi", "rad", "azimuth about z_0 of the rod's projection, from -y_0 towards x_0"),
                     Coordinate("chi", "rad", "elevation of the rod about the turned x axis")),
        links=(Link("gimbal", description="massless frame turned by psi about z_0"),
               Link("bob", mass=m.symbol, com=(0, -l.symbol, 0), description="point mass m at the rod's end")),
        joints=(Joint("psi", "revolute", WORLD, "gimbal", axis="z"),
                Joint("chi", "revolute", "gimbal", "bob", axis="x")),
        gravity=Gravity(g.symbol, (0, -1, 0)),
        doc="The spherical pendulum of Example 5.3 in a second spherical chart (harness/hard/charts.py).",
    )


# ----------------------------------------------------------------------------- toggle press, Exercise A.10
def toggle_press_chart_phi2(lecture: System) -> System:
    """The toggle press with ``phi_2`` as its coordinate: ``q = arcsin(L_2/L_1 sin phi_2)`` (A.100 solved for q),
    regular where the lecture's chart is not (``cos phi_2 = 0``) as long as ``L_1 > L_2`` and ``cos q != 0``."""
    import dataclasses
    L_1, L_2 = lecture.parameter("L_1").symbol, lecture.parameter("L_2").symbol
    phi_2 = Coordinate("phi_2", "rad", "angle of leg 2 (A.98) as the coordinate")
    q_of = sp.asin(L_2 / L_1 * sp.sin(phi_2.symbol))
    joints = (dataclasses.replace(lecture.joint("phi_1"), phi=q_of),
              dataclasses.replace(lecture.joint("theta_2"), phi=-phi_2.symbol - q_of))
    return dataclasses.replace(lecture, name="toggle_press_chart_phi2", coordinates=(phi_2,), joints=joints,
                               title="Toggle press in the chart phi_2")


def chart_dynamics(chart: Chart, scene, source: str) -> Dynamics:
    return Dynamics(chart.system, scene, source)
