"""Pictures of the mechanism for the report, by MuJoCo's own offscreen renderer from the exported MJCF (the file
the engines load, ``urdf/<system>.xml``, with its visual-only geoms: harness/export/mjcf.py ``add_visuals``).

Headless: MuJoCo's ``Renderer`` through EGL (``MUJOCO_GL=egl``, Debian's ``libegl1 libegl-mesa0
libgl1-mesa-dri``), else OSMesa (``libosmesa6``); the backend is chosen before ``mujoco`` is imported and
recorded in the picture's caption. Each picture shows the mechanism at a scene's initial state (else at
q = 0), seen along the axis the mechanism moves least in (the normal of a planar mechanism's plane), with the
lecture's coordinates marked at the joints they drive (θ = φ(q)). A scene's filmstrip shows a few frames of its
reference trajectory with the paths of one tracked point as each engine computed them drawn on every frame:
where the engines diverge, the paths separate.

Small files: 8-bit palette PNGs (a picture ≈ 10–30 kB).
"""

from __future__ import annotations

import importlib

import os
from pathlib import Path

import numpy as np

WIDTH, HEIGHT = 360, 270
FRAME = (200, 150)
FRAMES = 4
TIME_LINE = 16    # px under a filmstrip's frame for its time
VALUE_LINE = 14   # px for each line of the values a frame cannot show (:meth:`Scene3D.unseen`), under its time
_FONT = Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf")
_SOURCES = {"symbolic": (150, 150, 150), "pinocchio": (31, 119, 180), "mujoco": (214, 39, 40)}
_WIDTHS = {"symbolic": 6, "pinocchio": 3, "mujoco": 1}
_SERIES_NAMES = {"reference": "symbolic"}
"""A scene's series names the symbolic model's solution its reference (:func:`harness.scenes.trajectories.series`)."""
_BACKENDS = ("egl", "osmesa")
TENDON_WIDTH = 0.006   # of the picture's extent: a spatial tendon (a spring or damper between two points), 1-2 px
HIDDEN_GROUP = 5       # a tendon group no picture shows (MjvOption.tendongroup: groups 0-2 are shown)
UNSEEN_STEP = 0.7      # a coordinate's change that tests whether a picture shows it (rad or m: no symmetry's angle)
UNSEEN_TOLERANCE = 1e-9   # of the picture's world coordinates and rotation matrices: what does not move in round-off


def backend() -> str:
    """The OpenGL backend MuJoCo renders with: ``MUJOCO_GL`` if set, else EGL (set here, before ``mujoco``
    creates a context)."""
    os.environ.setdefault("MUJOCO_GL", "egl")
    os.environ.setdefault("PYOPENGL_PLATFORM", os.environ["MUJOCO_GL"])
    return os.environ["MUJOCO_GL"]


def _greek(name: str) -> str:
    """A coordinate name in the lecture's letters for a label (``phi_1`` → φ1, ``s_2`` → s2)."""
    from sympy.printing.pretty.pretty_symbology import greek_unicode

    parts = name.split("_")
    base = greek_unicode.get(parts[0], parts[0])
    return base + "".join(greek_unicode.get(p, p).translate(_SUBSCRIPT_DIGITS) for p in parts[1:])


_SUBSCRIPT_DIGITS = str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉")


FRAME_MARGIN = 1.15
"""The picture is this much larger than what it frames (7.5 % free on each side of the mechanism's extent), also
where perspective enlarges the parts nearer the camera."""
AXIS_VIEWS = ((180.0, 0.0), (90.0, 0.0), (90.0, -90.0))
"""Looking along -x (y to the right, z up), along +y (x to the right, z up), down -z (x to the right, y up)."""
OBLIQUE = tuple((azimuth, -30.0) for azimuth in (45.0, 135.0, 225.0, 315.0))
"""The oblique views: from above at 30°, from each quadrant."""
OBLIQUE_GAIN = 1.5
"""How much more of its most foreshortened link an oblique view must show than the square-on one to be taken: a
planar mechanism keeps its square-on view (which shows every link whole)."""


def _axes(azimuth: float, elevation: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """MuJoCo's free camera at ``azimuth``, ``elevation`` (degrees): the picture's right and up, and the direction
    it looks along, in world coordinates."""
    a, e = np.radians(azimuth), np.radians(elevation)
    forward = np.round([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)], 12) + 0.0   # an axis exactly
    right = np.round([np.sin(a), -np.cos(a), 0.0], 12) + 0.0
    return right, np.cross(right, forward), forward


def _shown(links: np.ndarray, azimuth: float, elevation: float) -> float:
    """The least fraction of its length any of ``links`` (vectors) shows in the view (1: every one seen square-on;
    0: one seen end-on); links of no length are left out."""
    length = np.linalg.norm(links, axis=1)
    some = length > 1e-9 * np.max(length, initial=0.0)
    if not some.any():
        return 1.0
    links, length = links[some], length[some]
    right, up, _ = _axes(azimuth, elevation)
    return float(np.min(np.linalg.norm(links @ np.column_stack([right, up]), axis=1) / length))


class Scene3D:
    """One system's MJCF in MuJoCo with a camera chosen for it and a projection of world points to pixels."""

    def __init__(self, system, xml: str, width: int = WIDTH, height: int = HEIGHT):
        backend()
        import mujoco

        from harness.derivation.compile import compiled
        from harness.engines.mujoco_engine import MujocoModel
        from harness.errors import ModelError
        from harness.export.numeric import instantiate

        self.mujoco, self.system = mujoco, system
        self.params = system.default_parameters()
        self.engine = MujocoModel(instantiate(system, self.params), xml=xml)   # the kinematics: the adapter's
        self.model, self.data = self.engine.model, self.engine.data
        for link in system.links:   # where the model says to draw a link elsewhere (Link.drawn_at): this copy only
            if any(link.drawn_at):
                body = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, link.name)
                if body < 0:
                    raise ModelError(f"link {link.name}: drawn_at: the MJCF has no body of that name (a massless "
                                     "link is merged with the link it carries): move that link instead")
                self.model.body_pos[body] += np.asarray(link.drawn_at, dtype=float)
        self.compiled = compiled(system)
        self.p = [self.params[s.name] for s in system.p]
        self.width, self.height = width, height
        self.slides = self._slides()
        self.labels = self._labels()
        self.renderer = mujoco.Renderer(self.model, height, width)
        self.option = mujoco.MjvOption()
        self.option.geomgroup[:] = 1
        self.option.sitegroup[:] = 0
        self.camera = mujoco.MjvCamera()

    def close(self) -> None:
        self.renderer.close()

    # ----------------------------------------------------------------- state
    def set_q(self, q) -> None:
        """Pose the tree at the lecture coordinates ``q`` (θ = φ(q))."""
        theta = np.ravel(self.compiled.map_at(np.asarray(q, float), np.zeros(len(q)), self.p,
                                              np.zeros(len(self.system.u)))[0])
        self.engine.pose(theta)

    def points(self) -> np.ndarray:
        """World positions that outline the mechanism: body origins, centres of mass, the 8 corners of each geom's
        bounding box in its own axes (MuJoCo's ``geom_aabb``: a long thin box or capsule is framed as it is, not as
        the cube around its bounding sphere; a sphere by that cube in world axes, which its turning does not
        move), sites, where the joints' labels stand (:meth:`joint_marks`: a pendulum's pivot, where its bob is a body
        merged with a massless link) and the ends of the lines of springs in prismatic joints (:meth:`slide_lines`)."""
        d, m = self.data, self.model
        corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
        local = m.geom_aabb[:, None, :3] + corners[None, :, :] * m.geom_aabb[:, None, 3:]   # (geoms, 8, 3)
        boxes = d.geom_xpos[:, None, :] + np.einsum("gij,gkj->gki", d.geom_xmat.reshape(-1, 3, 3), local)
        cubes = d.geom_xpos[:, None, :] + m.geom_rbound[:, None, None] * corners
        sphere = (m.geom_type == self.mujoco.mjtGeom.mjGEOM_SPHERE)[:, None, None]
        marks = np.reshape([point for point, _ in self.joint_marks()], (-1, 3))
        ends = np.reshape([point for line in self.slide_lines() for point in line], (-1, 3))
        return np.vstack([d.xpos[1:], d.xipos[1:], np.where(sphere, cubes, boxes).reshape(-1, 3), d.site_xpos,
                          marks, ends])

    # ----------------------------------------------------------------- camera
    def frame(self, states, shown=None) -> None:
        """Point the camera at the region the mechanism covers in the states ``shown`` (lecture coordinates; None:
        ``states``), from the view that shows its links least foreshortened over ``states`` (:meth:`view`)."""
        posed = [self._posed(q) for q in states]
        azimuth, elevation = self.view(np.vstack([p for p, _ in posed]), np.vstack([lk for _, lk in posed]))
        pts = np.vstack([p for p, _ in (posed if shown is None else map(self._posed, shown))])
        right, up, forward = _axes(azimuth, elevation)
        plane = np.column_stack([right, up])
        seen = pts @ plane
        size = float(max(np.max(np.ptp(seen, axis=0)), 0.2))
        centre = (pts.min(axis=0) + pts.max(axis=0)) / 2.0   # moved within the picture's plane to what it shows
        lookat = centre + plane @ ((seen.min(axis=0) + seen.max(axis=0)) / 2.0 - centre @ plane)
        self.camera.type = self.mujoco.mjtCamera.mjCAMERA_FREE
        self.camera.lookat[:] = lookat
        self.camera.azimuth, self.camera.elevation = azimuth, elevation
        half = np.tan(np.radians(self.model.vis.global_.fovy) / 2.0) * np.array([self.width / self.height, 1.0])
        # far enough that the points nearer the camera than the centre (a mechanism seen obliquely) fit as well
        nearer, off = (lookat - pts) @ forward, np.abs((pts - lookat) @ plane)
        fits = float(np.max(nearer + FRAME_MARGIN * np.max(off / half, axis=1)))
        self.camera.distance = max(FRAME_MARGIN * (size / 2.0) / half[1], fits)
        self.model.tendon_width[:] = TENDON_WIDTH * size   # a point spring or damper as a line seen at this size

    def _posed(self, q) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`points` and :meth:`links` of the mechanism posed at ``q``."""
        self.set_q(q)
        return self.points(), self.links()

    def links(self) -> np.ndarray:
        """The mechanism's links as vectors: from each body's parent's origin to its origin (a body carried by the
        world excepted), and from its origin to its centre of mass."""
        d, parent = self.data, self.model.body_parentid
        carried = [b for b in range(1, self.model.nbody) if parent[b] != 0]
        return np.vstack([d.xpos[carried] - d.xpos[parent[carried]], d.xipos[1:] - d.xpos[1:]])

    @staticmethod
    def view(pts: np.ndarray, links: np.ndarray) -> tuple[float, float]:
        """``(azimuth, elevation)`` in degrees: the view square-on (:data:`AXIS_VIEWS`) that foreshortens the
        most foreshortened of the ``links`` least (:func:`_shown`; a planar mechanism from the side its plane
        faces), an oblique one (:data:`OBLIQUE`) where that shows it :data:`OBLIQUE_GAIN` times as long; among
        views alike, along the least extent of ``pts``. The least extent alone is no guide where it hides a link
        end-on (a Furuta pendulum's arm, seen along itself; a tower crane's tower, seen from above)."""
        extent = np.ptp(pts, axis=0) + 1e-9 * np.arange(3)[::-1]   # ties: prefer z, then y
        shown = {view: round(_shown(links, *view), 6) for view in AXIS_VIEWS + OBLIQUE}
        square_on = max(AXIS_VIEWS, key=lambda view: (shown[view], -extent[AXIS_VIEWS.index(view)]))
        oblique = max(OBLIQUE, key=shown.get)
        return oblique if shown[oblique] > OBLIQUE_GAIN * shown[square_on] else square_on

    def render(self) -> np.ndarray:
        """The image, on a white background (pixels no object covers, from a segmentation pass)."""
        self.renderer.update_scene(self.data, camera=self.camera, scene_option=self.option)
        image = self.renderer.render().copy()
        self.renderer.enable_segmentation_rendering()
        try:
            self.renderer.update_scene(self.data, camera=self.camera, scene_option=self.option)
            empty = self.renderer.render()[:, :, 0] < 0
        finally:
            self.renderer.disable_segmentation_rendering()
        image[empty] = 255
        return image

    def project(self, points: np.ndarray) -> np.ndarray:
        """World points to pixel coordinates of the last rendered image: through the camera MuJoCo renders a mono
        image with, the average of its scene's two eyes (``mjv_averageCamera``). ``camera[0]`` alone is the left
        eye, half the interpupillary distance aside: every label and path had stood beside its body, 17.6 px to the
        right of the quarter car's wheel at 360 px."""
        scene = self.renderer.scene
        cam = self.mujoco.mjv_averageCamera(scene.camera[0], scene.camera[1])
        pos, forward, up = np.array(cam.pos), np.array(cam.forward), np.array(cam.up)
        right = np.cross(forward, up)
        v = np.atleast_2d(points) - pos
        depth = v @ forward
        depth = np.where(np.abs(depth) < 1e-9, 1e-9, depth)
        x = (v @ right) * cam.frustum_near / depth
        y = (v @ up) * cam.frustum_near / depth
        half_h = (cam.frustum_top - cam.frustum_bottom) / 2.0
        half_w = half_h * self.width / self.height
        px = (x - cam.frustum_center + half_w) / (2 * half_w) * self.width
        py = (1.0 - (y - cam.frustum_bottom) / (2 * half_h)) * self.height
        return np.stack([px, py], axis=1)

    # ----------------------------------------------------------------- marks
    def joint_marks(self) -> list[tuple[np.ndarray, str]]:
        """(world point, label) per tree joint: the lecture coordinates its θ depends on, at the joint's anchor; a
        prismatic joint's at its anchor moved by θ along the axis, on the body it moves (MuJoCo's ``xanchor`` of a
        slide joint is where θ = 0 puts it: a body that fell 39 km from it had its label at the ground)."""
        m, d = self.model, self.data
        marks = []
        for jid, label in self.labels:
            point = np.array(d.xanchor[jid])
            if m.jnt_type[jid] == self.mujoco.mjtJoint.mjJNT_SLIDE:
                point = point + d.qpos[m.jnt_qposadr[jid]] * np.array(d.xaxis[jid])
            marks.append((point, label))
        return marks

    def _labels(self) -> list[tuple[int, str]]:
        """(MuJoCo joint, label) per tree joint whose θ depends on lecture coordinates, those coordinates named
        (:meth:`joint_marks`; found once: :meth:`points` places the labels at every state it frames)."""
        import sympy as sp

        out = []
        for jid, expr in zip(self.engine.jids, self.system.phi):
            names = {s.name for s in sp.sympify(expr).free_symbols}
            used = [c.name for c in self.system.coordinates if c.name in names]
            if used:
                out.append((jid, ", ".join(_greek(u) for u in used)))
        return out

    def springs_and_dampers(self, effects=None) -> int:
        """Show the spatial tendons (springs and dampers between points) and the springs in prismatic joints
        (:meth:`slide_lines`) the scene ``effects`` call for, hide the others (a tendon group no picture shows; None:
        every one); how many tendons are shown."""
        shown = 0
        for i in range(self.model.ntendon):
            acts = effects is None or ("springs" in effects and self.model.tendon_stiffness[i] > 0) or (
                "dampers" in effects and self.model.tendon_damping[i] > 0)
            self.model.tendon_group[i] = 0 if acts else HIDDEN_GROUP
            shown += bool(acts)
        self.slides = self._slides(effects)
        return shown

    def _slides(self, effects=None) -> list[int]:
        """MuJoCo's joints of the prismatic tree joints that carry a spring (``JointSpring``), where the scene
        ``effects`` call for springs (None: every one). A damper in a joint is not drawn: it may be the joint's own
        viscous friction (the tower crane's trolley on its jib), not an element between two bodies."""
        from harness.modeling import JointSpring

        index = {j.name: k for k, j in enumerate(self.system.joints)}
        out = []
        for f in self.system.forces:
            if isinstance(f, JointSpring) and (effects is None or "springs" in effects):
                jid = self.engine.jids[index[f.joint]]
                if self.model.jnt_type[jid] == self.mujoco.mjtJoint.mjJNT_SLIDE and jid not in out:
                    out.append(jid)
        return out

    def slide_lines(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """A line per spring in a prismatic joint (:meth:`_slides`): from the origin of the body the joint is
        carried by to that of the body it moves, the two bodies between which it acts along the joint's axis (the
        quarter car's tyre from the road to the wheel, its suspension from the wheel to the body)."""
        m, d = self.model, self.data
        bodies = [m.jnt_bodyid[jid] for jid in self.slides]
        return [(np.array(d.xpos[m.body_parentid[b]]), np.array(d.xpos[b])) for b in bodies]

    def draw_slides(self, image) -> None:
        """:meth:`slide_lines` on ``image`` (the last rendered), black as MuJoCo draws a spatial tendon."""
        from PIL import ImageDraw

        draw = ImageDraw.Draw(image)
        for a, b in self.slide_lines():
            draw.line([tuple(p) for p in self.project(np.array([a, b]))], fill=(0, 0, 0), width=2)

    def tracked_point(self) -> np.ndarray:
        """The centre of mass of the body farthest down the tree (the end of the chain)."""
        return np.array(self.data.xipos[self.model.nbody - 1])

    def unseen(self, q) -> list[int]:
        """The lecture coordinates whose change at ``q`` moves nothing a picture shows: each moving geom stays where
        it is, turned at most about its own axis of symmetry (a sphere about any, a cylinder, a capsule or a round
        ellipsoid about its own), and the springs' ends, the joints' labels and the tracked point stay (a drive
        train's discs spinning, a top's spin). Tested by turning or moving each coordinate by :data:`UNSEEN_STEP`
        (in its own unit) alone: exact geometry, no rendering."""
        m, d = self.model, self.data
        moving = m.geom_bodyid > 0

        def drawn() -> tuple[np.ndarray, np.ndarray]:
            marks = np.vstack([d.geom_xpos[moving], d.site_xpos, d.xanchor, self.tracked_point()[None]])
            return marks, d.geom_xmat[moving].reshape(-1, 3, 3).copy()

        q = np.asarray(q, dtype=float)
        self.set_q(q)
        marks, turns = drawn()
        scale = UNSEEN_TOLERANCE * max(1.0, float(np.max(np.abs(marks))))
        kinds = m.geom_type[moving]
        sizes = m.geom_size[moving]
        mj = self.mujoco.mjtGeom
        out = []
        for i in range(len(q)):
            self.set_q(q + UNSEEN_STEP * np.eye(len(q))[i])
            moved, turned = drawn()
            if not np.isfinite(moved).all() or np.max(np.abs(moved - marks)) > scale:   # moved, or off the map's domain
                continue
            axis_kept = np.abs(turned[:, :, 2] - turns[:, :, 2]).max(axis=1) <= UNSEEN_TOLERANCE
            still = np.abs(turned - turns).max(axis=(1, 2)) <= UNSEEN_TOLERANCE
            round_about_z = np.isin(kinds, [mj.mjGEOM_CYLINDER, mj.mjGEOM_CAPSULE]) | (
                (kinds == mj.mjGEOM_ELLIPSOID) & np.isclose(sizes[:, 0], sizes[:, 1]))
            if np.all(still | (kinds == mj.mjGEOM_SPHERE) | (round_about_z & axis_kept)):
                out.append(i)
        self.set_q(q)
        return out


def _font(size: int):
    from PIL import ImageFont

    try:
        return ImageFont.truetype(str(_FONT), size)
    except OSError:
        return ImageFont.load_default()


def _annotate(image, scene: Scene3D, labels: bool = True):
    from PIL import ImageDraw

    draw = ImageDraw.Draw(image)
    font = _font(13)
    placed, marked = [], set()
    for anchor, text in scene.joint_marks() if labels else []:
        x, y = scene.project(anchor)[0]
        if not (0 <= x < scene.width and 0 <= y < scene.height):
            continue
        if (round(x), round(y), text) in marked:   # two joints at one point following the same coordinates (a slide
            continue                              # and a hinge rolling: one label says it)
        marked.add((round(x), round(y), text))
        draw.ellipse([x - 3, y - 3, x + 3, y + 3], outline=(0, 0, 0), width=2)
        tx, ty = x + 6, y - 16
        while any(abs(tx - px) < 30 and abs(ty - py) < 14 for px, py in placed):
            ty += 14
        placed.append((tx, ty))
        draw.text((tx, ty), text, fill=(0, 0, 0), font=font, stroke_width=2, stroke_fill=(255, 255, 255))
    return image


def _png(image, path: Path) -> tuple[int, int]:
    import io

    from harness.io import atomic_write_bytes

    buf = io.BytesIO()
    image.convert("RGB").quantize(colors=96, method=2, dither=0).save(buf, format="PNG", optimize=True)
    atomic_write_bytes(path, buf.getvalue())
    return image.size


def _states(system, scenes) -> list:
    n = len(system.coordinates)
    out = [np.zeros(n)]
    for sc in scenes:
        out.append(np.asarray(sc.q0, dtype=float))
    return out


CUBOIDS_DRAWN = ("body drawn as the homogeneous cuboid of its mass and inertia tensor (a cylinder where two of its "
                 "principal moments are equal, a sphere where all three are, a small sphere for a point mass), not as "
                 "its shape: a slender rod of large inertia is a long thin body")
CAPSULES_DRAWN = "thin capsules join each link's joint to its centre of mass and to its children's joints"


def _bodies_drawn(system) -> str:
    """The caption's words on how bodies are drawn: the solids a link is made of where the model says so
    (:attr:`Link.solids`), every other body as the solid equivalent to its inertia tensor (a cuboid, a cylinder or a
    sphere)."""
    made = [link.name for link in system.links if link.solids]
    if not made:
        return f"each {CUBOIDS_DRAWN}; {CAPSULES_DRAWN}"
    solids = f"{', '.join(made)} drawn as the solids the model makes {'it' if len(made) == 1 else 'them'} of"
    if len(made) == sum(link.has_mass for link in system.links):
        return f"{solids}; {CAPSULES_DRAWN}"
    return f"{solids}, each other {CUBOIDS_DRAWN}; {CAPSULES_DRAWN}"


def picture(system, xml: str, path: Path, scenes=()) -> dict:
    """The mechanism at its first scene's initial state (else q = 0), coordinates marked; writes ``path``."""
    from PIL import Image

    scene = Scene3D(system, xml)
    try:
        states = _states(system, scenes)
        q = states[1] if len(states) > 1 else states[0]
        scene.frame(states, shown=[q])   # framed around q alone: the other states are not drawn
        scene.set_q(q)
        image = Image.fromarray(scene.render())
        scene.draw_slides(image)
        image = _annotate(image, scene)
    finally:
        scene.close()
    size = _png(image, path)
    where = "at the initial state of scene " + scenes[0].name if scenes else "at q = 0"
    lines = "; lines: its springs and dampers between points (spatial tendons)" if scene.model.ntendon else ""
    return {"size": size, "caption": f"Rendered by MuJoCo ({backend()}) from {_mjcf_source(system)} {where}; "
                                      f"labels: the lecture coordinates each joint follows{lines}{_in_joints(system)}; "
                                      f"{_bodies_drawn(system)}{_drawn_elsewhere(system)}."}


def _drawn_elsewhere(system) -> str:
    """The caption's words on the links drawn away from where the model puts them (:attr:`Link.drawn_at`; empty
    where there are none)."""
    moved = [f"{link.name} by ({', '.join(f'{v:g}' for v in link.drawn_at)}) m"
             for link in system.links if any(link.drawn_at)]
    return f"; drawn moved from where the coordinates put them, for the picture only: {', '.join(moved)}" \
        if moved else ""


def _in_joints(system) -> str:
    """The caption's words on the springs and dampers in joints: a spring in a prismatic joint is a line between
    the two bodies it joins (:meth:`Scene3D.slide_lines`); the others are not drawn, coefficients of their joint's
    own coordinate with no points of their own to draw a line between (empty where there are none)."""
    from harness.modeling import JointDamper, JointSpring

    types = {j.name: j.type for j in system.joints}
    elements = [f for f in system.forces if isinstance(f, (JointSpring, JointDamper))]
    drawn = [f.name for f in elements if isinstance(f, JointSpring) and types[f.joint] == "prismatic"]
    others = [f.name for f in elements if f.name not in drawn]
    out = f"; black lines between the bodies a prismatic joint joins: its springs ({', '.join(drawn)})" if drawn else ""
    if others:
        out += (f"; not drawn: the {'other ' if drawn else ''}springs and dampers in joints ({', '.join(others)}), "
                "which act along their joint's own coordinate and have no points to draw a line between")
    return out


def filmstrip(system, xml: str, series: dict, path: Path, effects=None) -> dict:
    """A few frames of a scene's reference trajectory; on each, the path of the tracked point as every engine
    computed it (grey symbolic, wide; blue Pinocchio; red MuJoCo, thin) up to that frame's time, and the springs
    and dampers between points and the springs in prismatic joints the scene's ``effects`` call for
    (:meth:`Scene3D.springs_and_dampers`); under each frame's time, the values of the coordinates no frame can show
    (:meth:`Scene3D.unseen`)."""
    from PIL import Image, ImageDraw

    t = np.asarray(series["t"], dtype=float)
    named = {_SERIES_NAMES.get(name, name): s for name, s in series["sources"].items()}
    sources = {name: np.asarray(s["q"], dtype=float) for name, s in named.items()
               if name in _SOURCES and s.get("q") is not None}
    sources = {k: (v.reshape(len(t), -1) if v.ndim == 1 else (v if v.shape[0] == len(t) else v.T))
               for k, v in sources.items()}
    reference = sources.get("symbolic", next(iter(sources.values())))
    scene = Scene3D(system, xml, *FRAME)
    try:
        tendons = scene.springs_and_dampers(effects)
        step = max(1, len(t) // 200)
        paths = {}
        for name, q in sources.items():
            pts = []
            for k in range(0, len(t), step):
                scene.set_q(q[k])
                pts.append(scene.tracked_point())
            paths[name] = np.array(pts)
        scene.frame([reference[k] for k in range(0, len(t), max(1, len(t) // 20))])
        picks = np.linspace(0, len(t) - 1, FRAMES).round().astype(int)
        unseen = sorted({i for k in picks for i in scene.unseen(reference[k])})
        font = _font(11)
        values = [_values(system, reference[k], unseen, font) for k in picks]   # what a frame cannot show
        height = FRAME[1] + TIME_LINE + VALUE_LINE * max(map(len, values))
        strip = Image.new("RGB", (FRAME[0] * FRAMES, height), (255, 255, 255))
        for n, k in enumerate(picks):
            for row, text in enumerate(values[n]):   # under the frame's time
                ImageDraw.Draw(strip).text((n * FRAME[0] + 4, FRAME[1] + TIME_LINE - 1 + VALUE_LINE * row), text,
                                           fill=(0, 0, 0), font=font)
            scene.set_q(reference[k])
            image = Image.fromarray(scene.render())
            scene.draw_slides(image)
            draw = ImageDraw.Draw(image)
            upto = k // step + 1
            for name, pts in paths.items():  # widest first: where the lines coincide, every colour shows
                xy = [tuple(p) for p in scene.project(pts[:upto])]
                if len(xy) > 1:
                    draw.line(xy, fill=_SOURCES[name], width=_WIDTHS[name])
            strip.paste(image, (n * FRAME[0], 0))
            ImageDraw.Draw(strip).text((n * FRAME[0] + 4, FRAME[1] + 1), f"t = {t[k]:.2f} s", fill=(0, 0, 0),
                                       font=font)
    finally:
        scene.close()
    size = _png(strip, path)
    return {"size": size, "sources": sorted(paths), "tendons": tendons, "slides": len(scene.slides),
            "unseen": [_greek(system.coordinates[i].name) for i in unseen]}


def _values(system, q, indices, font) -> list[str]:
    """``φ₁ = 12.3 rad, φ₂ = −4.05 rad``: the coordinates ``indices`` at ``q`` to three digits, as lines of a frame's
    label no wider than the frame in ``font``."""
    lines: list[str] = []
    for i in indices:
        c = system.coordinates[i]
        value = f"{_greek(c.name)} = {q[i]:.3g} {c.unit}".replace("-", "\u2212")
        if lines and font.getlength(f"{lines[-1]}, {value}") <= FRAME[0] - 8:
            lines[-1] = f"{lines[-1]}, {value}"
        else:
            lines.append(value)
    return lines


def _exported(system) -> Path:
    """The system's exported MJCF, ``urdf/<system>.xml`` (a system outside the repository has none)."""
    from harness.cli import PROJECT_ROOT

    return PROJECT_ROOT / "urdf" / f"{system.name}.xml"


def _mjcf_source(system) -> str:
    """Where :func:`mjcf_text` takes a system's MJCF from, for a caption."""
    return f"urdf/{system.name}.xml" if _exported(system).is_file() else "its MJCF as harness export writes it"


def mjcf_text(system) -> str:
    """The MJCF the engines load at the default parameters: the exported ``urdf/<system>.xml`` (regenerated when
    the folder does not hold it)."""
    path = _exported(system)
    if path.is_file():
        return path.read_text()
    from harness.export.mjcf import mjcf_string
    from harness.export.numeric import instantiate

    return mjcf_string(instantiate(system, system.default_parameters()))


# --------------------------------------------------------------------------- the report's rendering process
class _NotKept(Exception):
    """A picture the cache does not hold, met where nothing is drawn (:func:`_render_system` with ``draw`` false)."""


def _render_system(job: dict, models: str, draw: bool = True) -> dict | None:
    """Picture and filmstrips of one system (in the rendering process; ``models``: the digest of the catalogue's
    files, :func:`harness.report.drawn.catalogue_digest`); failures are returned, not raised. ``draw`` false: only
    what the picture cache holds (in the report's own process), None when a picture is not kept."""
    import json

    from harness.report.drawn import drawn, key

    def drawing(make):
        if draw:
            return make

        def not_kept(path):
            raise _NotKept
        return not_kept

    catalogue, out = job["catalogue"], Path(job["out"])
    result: dict = {"picture": None, "strips": {}}
    try:
        system = catalogue.get(job["system"])
        xml = mjcf_text(system)
        target = f"figures/{system.name}.png"
        shown = drawn(out / target, key("mechanism", system.name, models, backend(), xml),
                      drawing(lambda path: picture(system, xml, path, catalogue.scenes(system.name))))
        result["picture"] = {"target": target, **shown}
    except _NotKept:
        return None
    except Exception as exc:  # noqa: BLE001 - reported on the page
        result["error"] = f"{type(exc).__name__}: {exc}"
        return result
    effects = {sc.name: set(sc.effects) for sc in catalogue.scenes(system.name)}
    for scene, series in job["scenes"]:
        target = f"figures/{system.name}.{scene}.strip.png"
        try:
            text = (out / series).read_bytes()
            strip = drawn(out / target, key("filmstrip", system.name, models, backend(), xml, text),
                          drawing(lambda path: filmstrip(system, xml, json.loads(text), path, effects.get(scene))))
            result["strips"][scene] = {"target": target, **strip}
        except _NotKept:
            return None
        except Exception as exc:  # noqa: BLE001 - a series the renderer cannot follow costs its strip only
            result["strips"][scene] = {"error": f"{type(exc).__name__}: {exc}"}
    return result


def _render_jobs(jobs: list[dict]) -> dict:
    backend()
    # MuJoCo's warnings go to the harness's handler, never to the console: compiling the MJCF runs MuJoCo at
    # qpos0, where the tower crane's M is singular — the warning the conformance run records and explains
    # (harness.engines.warnings_log); a picture is not a verdict
    importlib.import_module("harness.engines.warnings_log")
    from harness.report.drawn import catalogue_digest

    digests, rendered = {}, {}   # a catalogue's files read once, not once per system
    for job in jobs:
        catalogue = job["catalogue"]
        if id(catalogue) not in digests:
            digests[id(catalogue)] = catalogue_digest(catalogue)
        rendered[job["system"]] = _render_system(job, digests[id(catalogue)])
    return rendered


def render_all(jobs: list[dict]):
    """Start rendering every job (``{"system", "out", "catalogue", "scenes": [(scene, series path)]}``) in one
    separate process, whose MuJoCo is imported with ``MUJOCO_GL`` set (MuJoCo picks its OpenGL backend when imported,
    and an OpenGL failure may abort the process: the report's own process is unaffected); returns the function that
    waits for ``{system: result}``, so that the caller works while the process renders."""
    from concurrent.futures import ProcessPoolExecutor
    from multiprocessing import get_context

    def failed(exc) -> dict:
        reason = f"rendering process failed ({backend()}): {type(exc).__name__}: {exc}"
        return {job["system"]: {"picture": None, "strips": {}, "error": reason} for job in jobs}

    if not jobs:
        return dict
    backend()  # the spawned process inherits the environment
    kept, jobs = _kept_pictures(jobs)
    if not jobs:  # every picture is kept: nothing to render, no process started
        return lambda: kept
    try:
        pool = ProcessPoolExecutor(1, mp_context=get_context("spawn"))
        future = pool.submit(_render_jobs, jobs)
    except Exception as exc:  # noqa: BLE001 - no process: the pages say so
        return lambda error=exc: {**kept, **failed(error)}

    def result() -> dict:
        try:
            return {**kept, **future.result()}
        except Exception as exc:  # noqa: BLE001 - no OpenGL: the pages say so
            return {**kept, **failed(exc)}
        finally:
            pool.shutdown()
    return result


def _kept_pictures(jobs: list[dict]) -> tuple[dict, list[dict]]:
    """``({system: result}, the jobs left)``: the systems whose pictures the cache holds, read in this process
    (the rendering process costs 1.5-2 CPU s to start and import MuJoCo, every report; :func:`_render_system`
    without drawing), and the jobs with a picture to draw."""
    from harness.report.drawn import catalogue_digest

    kept, left, digests = {}, [], {}
    for job in jobs:
        catalogue = job["catalogue"]
        if id(catalogue) not in digests:
            digests[id(catalogue)] = catalogue_digest(catalogue)
        result = _render_system(job, digests[id(catalogue)], draw=False)
        if result is None:
            left.append(job)
        else:
            kept[job["system"]] = result
    return kept, left
