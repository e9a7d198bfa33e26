"""The phenomena a scene can call for: one plug-in module each, asked in turn by
:func:`harness.scenes.trajectories.run_scene` (the interface: :class:`harness.scenes.base.Phenomenon`).

* a **motion** simulates the scene and checks every source against the reference; exactly one per scene, first:
  the switching motion whose event the scene lists (:mod:`.stick_slip`, :mod:`.lift_off`), else :mod:`.smooth`;
* then, in this order, every plug-in of :data:`CHECKS` that applies: :mod:`.closures` (the constrained tree in the
  engines), :mod:`.rolling` (MuJoCo's contact), :mod:`.energy` (the energy balance), :mod:`.pruning`.

A new phenomenon is a module with a ``PLUGIN`` and a line here; a new kind of event is a value object in
:mod:`harness.modeling.events` and the plug-in whose ``event`` it is.
"""

from __future__ import annotations

from harness.scenes.phenomena import closures, energy, lift_off, pruning, rolling, smooth, stick_slip

SMOOTH = smooth.Smooth()
MOTIONS = (stick_slip.PLUGIN, lift_off.PLUGIN)
"""The switching motions, each called for by its event."""
CHECKS = (closures.PLUGIN, rolling.PLUGIN, energy.PLUGIN, pruning.PLUGIN)
"""The plug-ins asked after the motion, in the order their checks are recorded."""
BY_EVENT = {p.event: p for p in (*MOTIONS, *CHECKS) if p.event is not None}
"""The plug-in each kind of event calls for."""


def motion_of(scene):
    """The motion that simulates ``scene`` and the event it switches at: the first event of the scene that calls
    for a switching motion, else the smooth motion (no event)."""
    return next(((BY_EVENT[type(e)], e) for e in scene.events
                 if type(e) in BY_EVENT and BY_EVENT[type(e)] in MOTIONS), (SMOOTH, None))


def mujoco_own(scene):
    """The plug-in with a MuJoCo simulation of its own (dry friction, contact) the scene's events call for, and its
    event; None if there is none."""
    return next(((BY_EVENT[type(e)], e) for e in scene.events
                 if type(e) in BY_EVENT and BY_EVENT[type(e)].mujoco_run is not None), None)
