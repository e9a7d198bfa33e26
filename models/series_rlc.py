"""Series resonant circuit, Example 1.1 (Figure 1.4); (1.6)-(1.10).

Electrical: resistor ``R`` (1.6), capacitor ``C`` (1.7), inductor ``L`` (1.8), source voltage ``u`` in series
(1.9). With the capacitor charge ``Q = C u_c`` as coordinate and the current ``i_l = Q̇``, the mesh equation
(1.9c) is ``L Q̈ + R Q̇ + Q / C = u``: Lagrange's equations with ``T = L Q̇²/2`` (magnetic energy),
``V = Q²/(2C)`` (electric energy) and the dissipation of ``R``.

Engine treatment (honest analogue): no rigid-body engine simulates circuits. The engines get the
*mechanical analogue* — a mass ``L`` on a prismatic joint, a joint spring of stiffness ``1/C``, joint damping
``R`` and a motor force ``u`` — so they check the analogue's M, g, f_np and forward dynamics (force-voltage
analogy), not any electrical law; the state equation (1.10) in ``(i_l, u_c)`` is checked as a printed claim.
"""

from harness.modeling import (WORLD, Claim, Coordinate, Input, Joint, JointDamper, JointInput, JointSpring, Link,
                              Parameter, Scene, Step, System)

R = Parameter("R", 10.0, "Ohm", "resistance")
L = Parameter("L", 0.5, "H", "inductance (analogue: mass)")
C = Parameter("C", 1.0e-3, "F", "capacitance (analogue: compliance 1/stiffness)")
u = Input("u", "V", "source voltage (analogue: force)")
Q = Coordinate("Q", "C", "charge of the capacitor, Q = C u_c; Q_dot = i_l")

SYSTEM = System(
    name="series_rlc",
    title="Series resonant circuit (mechanical analogue in the engines)",
    lecture="Example 1.1; (1.6)-(1.10)",
    status="engines: mechanical analogue (mass L, stiffness 1/C, damping R, force u); no electrical law checked",
    coordinates=(Q,),
    links=(Link("charge", L, description="analogue mass L"),),
    joints=(Joint("Q", "prismatic", WORLD, "charge", axis="x"),),
    forces=(JointSpring("capacitor", "Q", 1 / C), JointDamper("resistor", "Q", R), JointInput("source", "Q", u)),
    doc=__doc__,
)

# (1.10), first row: d/dt i_l = (-u_c - R i_l + u)/L with i_l = Q_dot, u_c = Q/C. The second row,
# d/dt u_c = i_l / C, is the definition of the coordinate (Q = C u_c) and holds identically.
CLAIMS = [Claim("(1.10)", "eom", Q.accel - (-Q / C - R * Q.rate + u) / L, "d/dt i_l = (-u_c - R i_l + u)/L")]

SCENES = [
    Scene("step", "Example 1.1, (1.9c): the uncharged circuit switched onto a 10 V step at 0.1 s; damped "
          "oscillation (7 Hz, decay R/(2L) = 10/s) to Q = C u = 0.01 C (mechanical analogue in the engines)",
          (0.0,), (0.0,), 1.0, {"springs", "dampers", "inputs"}, inputs={u: Step(0.1, 10.0)}),
    Scene("lc_ring", "Example 1.1 with R = 0 (resistor left out): the capacitor charged to Q = 5 mC (5 V) "
          "discharges through the inductor, undamped LC oscillation (conservative)", (0.005,), (0.0,), 1.0,
          {"springs"}),
]
