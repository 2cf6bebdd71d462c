"""What ``report.html`` shows: the report's input, in one typed object.

A :class:`ReportSpec` holds the motion and everything drawn with it: a rigid
:class:`BodyLayer`, the :class:`Chart` objects, the :class:`Drawing` of moving
points, the checks, the extra sections, and the page's title, summary and frame
limits. :func:`poinsot.plotting.write_report` (``write_report(path, spec)``),
:func:`poinsot.plotting.report.report_html` (``report_html(spec)``) and
:func:`poinsot.plotting.show` (``show(spec)``) draw it; a scenario's kind makes one
(:meth:`poinsot.scenarios.ScenarioKind.report`). The keyword form of those
functions (``write_report(path, trajectory=..., inertia=...)``) is
:meth:`ReportSpec.from_keywords`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import InvalidInputError, InvalidTypeError

__all__ = ["Chart", "BodyLayer", "Drawing", "ReportSpec"]


@dataclass(frozen=True)
class Chart:
    """One chart of ``report.html``: named time series on the run's output times.

    Attributes
    ----------
    title : str
        Chart title (``"generalised coordinates q(t): angles"``).
    units : str
        Units of every series of the chart (``"rad"``; ``"relative"`` for ratios).
    series : Mapping[str, ndarray]
        Label -> values of shape (n,), one per output time.
    dashed : tuple of str
        Labels drawn dashed, in the colour of the series before them (e.g. a
        reference run over the run).

    Examples
    --------
    >>> Chart("position", "m", {"x": np.zeros(3)}).units
    'm'
    """

    title: str
    units: str
    series: Mapping[str, np.ndarray]
    dashed: tuple[str, ...] = ()


@dataclass(frozen=True)
class BodyLayer:
    """A rigid body in the scene of ``report.html``, turned by the attitude of the
    report's :class:`~poinsot.trajectory.Trajectory`.

    Attributes
    ----------
    shapes : mapping, sequence of mappings, or None
        The solids in body axes, each ``{"kind": KIND, "dims": DIMS}`` with KIND in
        :data:`poinsot.plotting.report.SHAPES` (dimensions in m), and optionally
        ``"center"`` (its centre of mass in body axes, m; default the origin) and
        ``"axes"`` (3x3 matrix whose columns are the solid's own axes in body
        axes); ``{"kind": "point", "dims": [0], "center": ...}`` for a point mass;
        or a triangle mesh ``{"kind": "mesh", "vertices": (m, 3) in m, "faces":
        (k, 3) indices}`` (drawn at ``axes @ v + center``; decimated by vertex
        clustering to at most 3000 faces). None: the uniform ellipsoid of the same
        ``mass`` and ``inertia`` at ``center_of_mass``.
    inertia : array_like, shape (3,) or (3, 3), or None
        Inertia tensor about the centre of mass, body axes (kg m^2).
    mass : float or None
        Mass (kg); with ``inertia`` and no ``shapes``, the equivalent uniform
        ellipsoid is drawn in metres (without it, the inertia ellipsoid scaled to
        a longest semi-axis of 1, and the axes say "scaled").
    center_of_mass : array_like, shape (3,), or None
        Centre of mass in body axes (m); None: the origin of the body axes.
    fixed_point : bool
        The origin of the body axes is fixed in space (a top's pin): marked.
    polhode : bool
        A torque-free body: the polhode and herpolhode are drawn (docs/theory.md
        §10). False for torqued or prescribed motions (their energy balance is
        then charted).

    Examples
    --------
    >>> BodyLayer(inertia=np.diag([1.0, 2.0, 3.0]), polhode=True).fixed_point
    False
    """

    shapes: Mapping[str, Any] | Sequence[Mapping[str, Any]] | None = None
    inertia: Any = None
    mass: float | None = None
    center_of_mass: Any = None
    fixed_point: bool = False
    polhode: bool = False


@dataclass(frozen=True)
class Drawing:
    """Points that move with the motion, drawn in the scene of ``report.html``
    (space axes, m): a Lagrangian system's ``[draw]`` table, a top's stem and axis
    tip, a pendulum's swing plane. With a rigid body the points are drawn with it;
    without one, frames are chosen from the motion's own time scale (at least 24
    per period of the fastest back-and-forth of a point).

    Attributes
    ----------
    points : Mapping[str, ndarray]
        Name -> positions of shape (n, 3), one per output time.
    links : tuple of (str, str)
        Segments drawn between two points at every frame.
    trails : tuple of str
        Points whose path up to the frame's time is drawn, older parts fading.
    guides : Mapping[str, ndarray]
        Label -> the two ends of a dashed segment at each output time, shape
        (n, 2, 3) (e.g. the direction of a pendulum's swing plane).
    face_on : bool
        A plane drawing in the x-z plane: the view starts facing it.

    Examples
    --------
    >>> d = Drawing({"pivot": np.zeros((2, 3)), "bob": np.ones((2, 3))}, (("pivot", "bob"),))
    >>> d.mapping()["links"]
    [('pivot', 'bob')]
    """

    points: Mapping[str, np.ndarray] = field(default_factory=dict)
    links: tuple[tuple[str, str], ...] = ()
    trails: tuple[str, ...] = ()
    guides: Mapping[str, np.ndarray] = field(default_factory=dict)
    face_on: bool = False

    def mapping(self) -> dict[str, Any]:
        """As the keyword form takes it (``write_report(..., drawing=...)``)."""
        return {"points": dict(self.points), "links": list(self.links),
                "trails": list(self.trails), "guides": dict(self.guides),
                "face_on": self.face_on}  # fmt: skip


@dataclass(frozen=True)
class ReportSpec:
    """What ``report.html`` shows: drawn by :func:`poinsot.plotting.write_report`,
    :func:`poinsot.plotting.report.report_html` and :func:`poinsot.plotting.show`;
    made by a scenario's kind (:meth:`poinsot.scenarios.ScenarioKind.report`) or by
    :meth:`from_keywords`.

    Attributes
    ----------
    motion : Result
        The result the page animates, on its times ``t`` of shape ``(n,)``: a
        :class:`~poinsot.trajectory.Trajectory` of ONE body turns the ``body``
        layer (with its ``momentum`` when present); a result with a ``position``
        of shape ``(n, 3)`` (a :class:`~poinsot.trajectory.PointTrajectory`) is
        drawn as a point and its path (in the axes its ``frame_name`` names); any
        other result has no scene, only its charts and checks.
    body : BodyLayer or None
        The rigid body drawn (with a Trajectory ``motion``); None: no shape, no
        fixed point, no polhode.
    reference : Trajectory or None
        A rigid body's reference run on the same times: its axes dashed, its ``w``
        overlaid, the attitude error ``|log(R_ref^-1 R)|`` plotted (ignored for
        other results: show their differences as ``charts``).
    torque : array_like, shape (n, 3), or None
        Torque on a rigid body in body axes (N m) at each sample: plotted, with the
        energy balance ``T(t) - T(0) = int N . w dt`` when ``energy`` is known.
    euler_seq : str
        Sequence of the attitude angles plotted for a rigid body (``"ZXZ"``
        precession, nutation, spin; ``"ZYX"`` yaw, pitch, roll).
    charts : tuple of Chart
        Extra charts, shown first (e.g. a Lagrangian system's ``q_i(t)``).
    checks : tuple of poinsot.scenarios.Check
        Quantities with a known behaviour: conserved ones plotted as a relative
        change (their maximum stated), the others as values with units.
    sections : tuple of (str, str)
        Extra ``(heading, html)`` sections shown above the summary (trusted HTML
        made by poinsot, e.g. a kind's figures as inline SVG; not user text).
    drawing : Drawing or None
        Points, links, trails and guides drawn in the scene with the motion.
    title : str
        Title of the page.
    summary : mapping or None
        The run's summary (e.g. ``summary.json``): top-level mappings are shown as
        sections, each with its ``"units"`` mapping; the raw JSON is collapsible.
    max_frames : int
        Largest number of animation frames, in [2, 20000].
    max_frame_angle : float
        Largest turn of the body between two frames (degrees), in (0, 90]: frames
        are added where the body turns fast, so that a spin never strobes. If
        ``max_frames`` or the output samples do not allow it, the page says the
        largest turn between frames.

    Examples
    --------
    >>> import numpy as np, poinsot
    >>> t = np.linspace(0.0, 1.0, 11)
    >>> tr = poinsot.Trajectory(t, poinsot.Rotation.from_rotvec(np.outer(t, [0, 0, 1.0])),
    ...                         np.tile([0.0, 0.0, 1.0], (11, 1)), "spin")
    >>> spec = ReportSpec(tr, BodyLayer(inertia=[1.0, 2.0, 3.0], mass=1.0), title="spin")
    >>> spec == ReportSpec.from_keywords(trajectory=tr, inertia=[1.0, 2.0, 3.0], mass=1.0,
    ...                                  free_body=False, title="spin")
    True
    """

    motion: Any
    body: BodyLayer | None = None
    reference: Any = None
    torque: Any = None
    euler_seq: str = "ZYX"
    charts: tuple[Chart, ...] = ()
    checks: tuple[Any, ...] = ()
    sections: tuple[tuple[str, str], ...] = ()
    drawing: Drawing | None = None
    title: str = "poinsot report"
    summary: Mapping[str, Any] | None = None
    max_frames: int = 1500
    max_frame_angle: float = 20.0

    @classmethod
    def from_keywords(
        cls,
        *,
        trajectory: Any,
        summary: Mapping[str, Any] | None = None,
        title: str = "poinsot report",
        shape: Mapping[str, Any] | Sequence[Mapping[str, Any]] | None = None,
        inertia: Any = None,
        mass: float | None = None,
        center_of_mass: Any = None,
        fixed_point: bool = False,
        free_body: bool = True,
        checks: Sequence[Any] = (),
        torque: Any = None,
        euler_seq: str = "ZYX",
        reference: Any = None,
        max_frames: int = 1500,
        max_frame_angle: float = 20.0,
        sections: Sequence[tuple[str, str]] = (),
        series: Sequence[tuple[Any, ...]] = (),
        drawing: Mapping[str, Any] | None = None,
    ) -> ReportSpec:
        """The spec of the keyword form, ``write_report(path, trajectory=..., ...)``.

        Parameters
        ----------
        trajectory : Result
            The :attr:`motion`.
        shape, inertia, mass, center_of_mass, fixed_point : optional
            The :class:`BodyLayer` (``shape`` is its ``shapes``: one mapping or a
            sequence of them).
        free_body : bool, optional
            True (default) for a torque-free body: the layer's ``polhode``.
        summary, title, checks, torque, euler_seq, reference, max_frames, \
max_frame_angle, sections : optional
            The fields of the same names (defaults: the spec's).
        series : sequence of (str, str, mapping[, collection]), optional
            The :attr:`charts`, each ``(title, units, {label: values of shape
            (n,)})``; an optional fourth item names the labels drawn dashed.
        drawing : mapping, optional
            The :class:`Drawing` as a mapping: ``{"points": {name: (n, 3)},
            "links": [(name, name), ...], "trails": [name, ...], "guides":
            {label: (n, 2, 3)}, "face_on": bool}``.

        Returns
        -------
        ReportSpec

        Raises
        ------
        InvalidTypeError
            If ``series`` is not a sequence of ``(title, units, mapping)`` or
            ``drawing`` not a mapping.
        InvalidInputError
            If ``drawing`` has other keys. The values are checked when the spec
            is drawn.

        Examples
        --------
        >>> spec = ReportSpec.from_keywords(trajectory=None, inertia=[1.0, 2.0, 3.0],
        ...                                 series=[("q", "rad", {"a": np.zeros(2)})])
        >>> spec.body.polhode, spec.charts[0].title, spec.drawing
        (True, 'q', None)
        """
        body = BodyLayer(shape, inertia, mass, center_of_mass, bool(fixed_point), bool(free_body))
        return cls(
            motion=trajectory, body=body, reference=reference, torque=torque,
            euler_seq=euler_seq, charts=_charts(series), checks=tuple(checks),
            sections=tuple(sections), drawing=_drawing(drawing), title=title,
            summary=summary, max_frames=max_frames, max_frame_angle=max_frame_angle,
        )  # fmt: skip


def _charts(series: Any) -> tuple[Chart, ...]:
    """``(title, units, {label: values}[, dashed])`` items as charts."""
    if isinstance(series, str | Mapping) or not isinstance(series, Sequence):
        raise InvalidTypeError(
            "Expected `series` to be a sequence of (title, units, {label: values}), got "
            f"{type(series).__name__}."
        )
    out = []
    for item in series:
        if (
            not isinstance(item, Sequence)
            or len(item) not in (3, 4)
            or not isinstance(item[0], str)
            or not isinstance(item[1], str)
            or not isinstance(item[2], Mapping)
        ):
            raise InvalidTypeError(
                "Expected each of `series` to be (title: str, units: str, {label: values}), "
                f"got {item!r:.80}."
            )
        out.append(Chart(item[0], item[1], item[2], tuple(item[3]) if len(item) == 4 else ()))
    return tuple(out)


def _drawing(drawing: Any) -> Drawing | None:
    """A ``{"points": ..., "links": ..., ...}`` mapping as a :class:`Drawing`."""
    if drawing is None:
        return None
    if not isinstance(drawing, Mapping):
        raise InvalidTypeError(
            f"Expected `drawing` to be a mapping or None, got {type(drawing).__name__}."
        )
    unknown = set(drawing) - {"points", "links", "trails", "guides", "face_on"}
    if unknown:
        raise InvalidInputError(
            "Expected `drawing` to have the keys 'points', 'links', 'trails', 'guides', "
            f"'face_on', got {sorted(drawing)}."
        )
    return Drawing(
        points=drawing.get("points") or {},
        links=tuple(drawing.get("links") or ()),
        trails=tuple(drawing.get("trails") or ()),
        guides=drawing.get("guides") or {},
        face_on=bool(drawing.get("face_on", False)),
    )
