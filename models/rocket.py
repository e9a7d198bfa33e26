"""Single-stage rocket with time-varying mass, Exercise 3.6.

Height ``h`` above the Earth's surface along ``e_h = e_z``, gravity ``g`` in ``-e_z``; mass ``m(t) = m_0 - m_f(t)``
with the fuel ejection rate ``m_f' = u(t)`` at the relative velocity ``-w e_h``. The solution reads
``h' = v``, ``v' = -g + w u / m``, ``m' = -u``: the thrust ``w u`` acts on the current mass ``m``.

Engine treatment: rigid-body engines have constant masses. The model holds the *current* mass ``m`` as a
parameter (every drawn state has its own ``m``) and the thrust ``w u`` as an external force, so the engines
check the instantaneous dynamics ``m h'' = -m g + w u``. Mass depletion ``m' = -u`` is not mechanics of a
rigid body and is not simulated: the burn scene holds the mass at the parameter's value (the 20 kg burnt
in it are 4 % of the mass; its description says so).
"""

from harness.modeling import (WORLD, Claim, Coordinate, Gravity, Input, Joint, Link, Parameter, Point, PointForce,
                              Scene, Step, System, standard_gravity)

m = Parameter("m", 500.0, "kg", "current mass of the rocket m(t) = m_0 - m_f(t)")
w = Parameter("w", 2500.0, "m/s", "relative velocity of the ejected fuel")
g = standard_gravity()
u = Input("u", "kg/s", "fuel ejection rate dm_f/dt")
h = Coordinate("h", "m", "height above the Earth's surface", range=(0.0, 1.0e5))

SYSTEM = System(
    name="rocket",
    title="Single-stage rocket (instantaneous mass)",
    lecture="Exercise 3.6",
    status="engines: instantaneous dynamics at the current mass; mass depletion m' = -u not simulated",
    coordinates=(h,),
    links=(Link("rocket", m),),
    joints=(Joint("h", "prismatic", WORLD, "rocket", axis="z"),),
    gravity=Gravity(g, (0, 0, -1)),
    forces=(PointForce("thrust", Point("rocket", (0, 0, 0), "nozzle"), (0, 0, w * u)),),
    doc=__doc__,
)

CLAIMS = [Claim("Solution of Exercise 3.6", "eom", h.accel - (-g + w * u / m), "v' = -g + w u / m")]

SCENES = [
    Scene("burn", "Exercise 3.6: lift-off from rest at h = 0, fuel ejection rate u = 4 kg/s (thrust w u = 10 kN) "
          "throttled up to 6 kg/s at 2 s. The mass m is the parameter at its current value (500 kg): mass "
          "depletion m' = -u (here 20 kg, 4 %) is not modeled in the engines", (0.0,), (0.0,), 4.0,
          {"gravity", "external"}, inputs={u: Step(2.0, 6.0, before=4.0)}),
]
