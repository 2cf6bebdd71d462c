"""Events: the times at which a function of the state crosses zero (theory §11.1), for
every integrator of poinsot (re-exported by :mod:`poinsot.dynamics`).

Every integrator of poinsot takes ``events=``, as SciPy's ``solve_ivp`` does: a
function ``g(t, y)`` of the time (s) and the state ``y`` (the layout of each
integrator below), or a list of them, or :class:`Event` objects. An event of ``g`` is a
time ``t*`` with ``g(t*, y(t*)) = 0`` where ``g`` changes sign.

How it is found (per body of a batch): ``g`` is evaluated at the output times; in each
output interval where its sign changes (in the ``direction`` asked for), the motion is
integrated again from the sample at the start of the interval by DOP853 at ``rtol =
1e-13`` with dense output, and ``t*`` is the root of ``g`` on that dense output
(Brent's method to a few ulps of ``t``). So ``t*`` is as accurate as the computed
motion at the start of the interval, not as coarse as the output grid. Like SciPy
(which looks between its steps), an event is seen only where ``g`` differs in sign at
two consecutive output times: two crossings inside one output interval cancel. Choose
output times closer than half the shortest time between events.

A **terminal** event ends the motion: one body alone (``y`` has no batch) returns
the samples before ``t*`` and then the state at ``t*`` as its last sample; in a batch
the other bodies go on, and a body that stopped is held at its state at ``t*`` from
then on (its stop time is ``EventLog.t_stop``). ``terminal`` may be a count: the motion
ends at that occurrence.

State layouts ``y``:

- rigid bodies (:func:`poinsot.dynamics.simulate`,
  :meth:`~poinsot.dynamics.HeavyRigidBody.simulate`): ``(q_w, q_x, q_y, q_z, w_x, w_y,
  w_z)``, the attitude body -> space (scalar first) and the angular velocity in body
  axes (rad/s);
- particles (:func:`poinsot.dynamics.simulate_particle`): ``(x, y, z, v_x, v_y, v_z)``
  in the frame's axes (m, m/s);
- Lagrangian systems (:meth:`poinsot.symbolic.LagrangeSystem.simulate`): ``(q_1 ...
  q_n, q'_1 ... q'_n)``.

``g`` is called with one body's state (shape ``(d,)``, returning a float) and, to scan
the samples, with a batch's states at one time (shape ``batch + (d,)``, returning the
batch shape): write it with ``y[..., k]`` and it serves both.

Examples
--------
A ball thrown up at 10 m/s lands when ``z = 0``, after ``2 v0 / g``:

>>> import numpy as np
>>> from poinsot.dynamics import simulate_particle
>>> from poinsot.kinematics import FrameMotion
>>> ground = Event(lambda t, y: y[..., 2], terminal=True, direction=-1, name="ground")
>>> tr = simulate_particle(FrameMotion(), [0, 0, -9.81], [0, 0, 0], [3.0, 0, 10.0],
...                        np.linspace(0.0, 5.0, 51), events=[ground])
>>> t_land = tr.info["events"].times("ground")
>>> np.allclose(t_land, 2 * 10.0 / 9.81, rtol=1e-12), bool(tr.t[-1] == t_land[0])
(True, True)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ._typing import FloatArray
from .errors import IntegrationError, InvalidInputError, InvalidTypeError

__all__ = ["Event", "EventLog", "as_events"]

#: tolerances of the dense re-integration that locates an event inside an interval
_RTOL, _ATOL = 1e-13, 1e-15


@dataclass(frozen=True)
class Event:
    """A function of the state whose zeros are events (SciPy's ``events=`` convention).

    Parameters
    ----------
    function : callable
        ``g(t, y) -> float`` (see the module docstring for the layout of ``y``).
    terminal : bool or int, optional
        ``True``: the motion ends at the first event; a count ``k >= 1``: at the
        ``k``-th; ``False`` (default): the events are only recorded.
    direction : float, optional
        ``> 0``: only crossings from negative to positive; ``< 0``: positive to
        negative; ``0`` (default): both.
    name : str, optional
        A name for :meth:`EventLog.times` (default: the function's ``__name__``, or
        ``"event<i>"``).

    Examples
    --------
    >>> Event(lambda t, y: y[..., 0], terminal=True, direction=-1, name="x=0").terminal
    1
    """

    function: Callable[..., Any]
    terminal: int = 0
    direction: float = 0.0
    name: str = ""

    def __post_init__(self) -> None:
        if not callable(self.function):
            raise InvalidTypeError(
                "Expected an event `function` g(t, y) -> float, got "
                f"{type(self.function).__name__}."
            )
        term = self.terminal
        if isinstance(term, (bool, np.bool_)):
            term = int(bool(term))
        elif isinstance(term, (int, np.integer)) and term >= 0:
            term = int(term)
        else:
            raise InvalidInputError(
                f"Expected an event's `terminal` to be a bool or a count >= 0, got {term!r}."
            )
        try:
            d = float(self.direction)
        except (TypeError, ValueError):
            raise InvalidTypeError(
                f"Expected an event's `direction` to be a number, got {self.direction!r}."
            ) from None
        if not math.isfinite(d):
            raise InvalidInputError(f"Expected a finite event `direction`, got {d!r}.")
        object.__setattr__(self, "terminal", term)
        object.__setattr__(self, "direction", float(np.sign(d)))
        if not isinstance(self.name, str):
            raise InvalidTypeError(f"Expected an event's `name` to be a str, got {self.name!r}.")


def as_events(events: Any, arg: str = "events") -> tuple[Event, ...]:
    """``events=`` as a tuple of :class:`Event`: a callable (its ``terminal`` and
    ``direction`` attributes are read, as SciPy does), an :class:`Event`, or a sequence
    of them; names default to the function's ``__name__`` (else ``event<i>``) and must
    differ.

    >>> def hit(t, y): return y[..., 2]
    >>> hit.terminal = True
    >>> [(e.name, e.terminal) for e in as_events(hit)]
    [('hit', 1)]
    """
    if events is None:
        return ()
    items = [events] if (callable(events) or isinstance(events, Event)) else events
    if not isinstance(items, (list, tuple)):
        raise InvalidTypeError(
            f"Expected `{arg}` to be a function g(t, y), an Event or a list of them, "
            f"got {type(events).__name__}."
        )
    out: list[Event] = []
    for i, e in enumerate(items):
        if not isinstance(e, Event):
            if not callable(e):
                raise InvalidTypeError(
                    f"Expected `{arg}[{i}]` to be a function g(t, y) or an Event, "
                    f"got {type(e).__name__}."
                )
            e = Event(e, getattr(e, "terminal", False), getattr(e, "direction", 0.0))
        name = e.name or getattr(e.function, "__name__", "")
        if not name or name == "<lambda>":
            name = f"event{i}"
        out.append(Event(e.function, e.terminal, e.direction, name))
    names = [e.name for e in out]
    if len(set(names)) != len(names):
        raise InvalidInputError(
            f"Expected the events of `{arg}` to have distinct names, got {names}."
        )
    return tuple(out)


@dataclass(frozen=True, eq=False)
class EventLog:
    """The events of a run, one row per occurrence, in time order per body.

    Attributes
    ----------
    names : tuple of str
        The events' names (``event[k]`` indexes them).
    event : ndarray of int, shape (k,)
        Which event.
    body : ndarray of int, shape (k,)
        Which body of the batch (flat C-order index; 0 for one body).
    t : ndarray, shape (k,)
        The event times (s).
    state : ndarray, shape (k, d)
        The state at each event (the integrator's layout, module docstring).
    direction : ndarray, shape (k,)
        +1 where ``g`` went from negative to positive, -1 the other way.
    t_stop : ndarray, shape batch
        The time each body stopped at a terminal event (``inf``: it did not stop).
    batch : tuple of int
        The batch shape of the run.

    Examples
    --------
    >>> log = EventLog(("hit",), np.array([0]), np.array([0]), np.array([1.5]),
    ...                np.zeros((1, 6)), np.array([-1.0]), np.array(1.5), ())
    >>> log.times("hit"), log.t_events
    (array([1.5]), [array([1.5])])
    """

    names: tuple[str, ...]
    event: np.ndarray
    body: np.ndarray
    t: np.ndarray
    state: np.ndarray
    direction: np.ndarray
    t_stop: np.ndarray
    batch: tuple[int, ...]

    def _which(self, event: int | str) -> int:
        if isinstance(event, str):
            if event not in self.names:
                raise InvalidInputError(
                    f"Expected `event` to be one of {list(self.names)}, got {event!r}."
                )
            return self.names.index(event)
        k = int(event)
        if not 0 <= k < len(self.names):
            raise InvalidInputError(
                f"Expected `event` to be an index below {len(self.names)}, got {event!r}."
            )
        return k

    def _rows(self, event: int | str, body: int | tuple[int, ...] | None) -> np.ndarray:
        rows = self.event == self._which(event)
        if body is not None:
            idx = (body,) if isinstance(body, (int, np.integer)) else tuple(body)
            try:
                flat = int(np.ravel_multi_index(idx, self.batch)) if self.batch else 0
            except (ValueError, TypeError):
                raise InvalidInputError(
                    f"Expected `body` to index the batch of shape {self.batch}, got {body!r}."
                ) from None
            rows &= self.body == flat
        elif self.batch and math.prod(self.batch) > 1:
            raise InvalidInputError(
                "Expected `body` (an index into the batch) for a batch of bodies."
            )
        return rows

    def times(self, event: int | str = 0, body: int | tuple[int, ...] | None = None) -> FloatArray:
        """The times (s) of ``event`` (name or index) for ``body`` (an index into the
        batch; may be left out for one body), increasing."""
        return self.t[self._rows(event, body)]

    def states(self, event: int | str = 0, body: int | tuple[int, ...] | None = None) -> FloatArray:
        """The states at those times, shape (k, d)."""
        return self.state[self._rows(event, body)]

    @property
    def t_events(self) -> list[FloatArray]:
        """SciPy's layout for one body: a list with each event's times."""
        return [self.times(i, 0 if self.batch else None) for i in range(len(self.names))]

    @property
    def y_events(self) -> list[FloatArray]:
        """SciPy's layout for one body: a list with each event's states, (k, d)."""
        return [self.states(i, 0 if self.batch else None) for i in range(len(self.names))]

    def __len__(self) -> int:
        return int(self.t.size)

    @classmethod
    def of_one_body(
        cls,
        names: tuple[str, ...],
        rows: list[tuple[float, int, np.ndarray, float]],
        width: int,
        t_stop: float = math.inf,
    ) -> EventLog:
        """The log of one body's run from its rows ``(t, event index, state (width,),
        direction)``, in time order (the switching integrators build it this way).

        >>> EventLog.of_one_body(("hit",), [(1.5, 0, np.zeros(2), -1.0)], 2).times()
        array([1.5])
        """
        return cls(
            names=tuple(names),
            event=np.array([r[1] for r in rows], dtype=np.int64),
            body=np.zeros(len(rows), dtype=np.int64),
            t=np.array([r[0] for r in rows], dtype=float),
            state=np.array([r[2] for r in rows], dtype=float).reshape(len(rows), width),
            direction=np.array([r[3] for r in rows], dtype=float),
            t_stop=np.array(t_stop),
            batch=(),
        )

    def __repr__(self) -> str:
        counts = ", ".join(
            f"{n}: {int(np.count_nonzero(self.event == i))}" for i, n in enumerate(self.names)
        )
        return f"EventLog({counts})"


Flow = Callable[[np.ndarray, float, float, np.ndarray], Callable[[float], np.ndarray]]


def _scan(g: Callable[..., Any], t: FloatArray, y: FloatArray, name: str) -> FloatArray:
    """``g`` at every sample: (n, N) from ``y`` (n, N, d), one call per output time."""
    n, nb = y.shape[0], y.shape[1]
    out = np.empty((n, nb))
    for k in range(n):
        v = np.asarray(g(float(t[k]), y[k]), dtype=float)
        if v.shape not in ((nb,), ()) and v.size != nb:
            raise InvalidInputError(
                f"Expected event {name!r} to return one value per body ({nb}), got shape {v.shape}."
            )
        out[k] = np.broadcast_to(v.reshape(-1) if v.ndim else v, (nb,))
    if not np.all(np.isfinite(out)):
        k, b = np.argwhere(~np.isfinite(out))[0]
        raise IntegrationError(
            f"Event {name!r} returned a non-finite value at t = {float(t[k]):.6g} s (body {b})."
        )
    return out


def _root(f: Callable[[float], float], a: float, b: float, fa: float, fb: float) -> float:
    from scipy.optimize import brentq

    if fb == 0.0:
        return b
    if fa == 0.0:
        return a
    if np.sign(fa) == np.sign(fb):  # the re-integrated motion moved the root out: the edge
        return a if abs(fa) < abs(fb) else b
    eps = np.finfo(float).eps
    return float(brentq(f, a, b, xtol=4 * eps * max(abs(a), abs(b), 1e-300), rtol=4 * eps))


def locate(
    events: tuple[Event, ...],
    t: FloatArray,
    y: FloatArray,
    flow: Flow,
    batch: tuple[int, ...],
) -> tuple[FloatArray, FloatArray, EventLog]:
    """Find the events of the samples ``y`` (n, N, d) at ``t`` (n,); return the
    samples as the caller should keep them (cut or held at terminal events) and the
    :class:`EventLog`.

    ``flow(bodies, t0, t1, y0)`` integrates the bodies ``bodies`` (index array) from
    the batch's states ``y0`` (N, d) at ``t0`` to ``t1`` and returns a dense solution
    ``s(t) -> (len(bodies), d)`` (a flow may integrate only those bodies, or all of
    them when their right-hand sides are coupled, as by a torque of the whole batch).
    """
    n, nb, d = y.shape
    names = tuple(e.name for e in events)
    rows: list[tuple[float, int, int, FloatArray, float]] = []
    if n > 1 and events:
        gs = [_scan(e.function, t, y, e.name) for e in events]
        # intervals (k, body) with a sign change of some event
        hits = np.zeros((n - 1, nb), dtype=bool)
        masks = []
        for e, g in zip(events, gs, strict=True):
            up = (g[:-1] < 0) & (g[1:] >= 0)
            down = (g[:-1] > 0) & (g[1:] <= 0)
            m = up if e.direction > 0 else down if e.direction < 0 else (up | down)
            masks.append(m)
            hits |= m
        for k in np.flatnonzero(hits.any(axis=1)):
            bodies = np.flatnonzero(hits[k])
            a, b = float(t[k]), float(t[k + 1])
            sol = flow(bodies, a, b, y[k])
            for j, body in enumerate(bodies):
                for i, (e, g, m) in enumerate(zip(events, gs, masks, strict=True)):
                    if not m[k, body]:
                        continue

                    def f(s: float, e: Event = e, j: int = j, sol: Any = sol) -> float:
                        return float(e.function(s, sol(s)[j]))

                    ts = _root(f, a, b, f(a), f(b))
                    sign = 1.0 if g[k + 1, body] > g[k, body] else -1.0
                    rows.append((ts, int(body), i, np.array(sol(ts)[j], dtype=float), sign))
    rows.sort(key=lambda r: (r[1], r[0], r[2]))
    # terminal events: the first occurrence that reaches its count stops the body
    t_stop = np.full(nb, np.inf)
    kept: list[tuple[float, int, int, FloatArray, float]] = []
    counts: dict[tuple[int, int], int] = {}
    for r in rows:
        ts, who, i, state, sign = r
        owner = int(who)
        if ts > t_stop[owner]:
            continue
        kept.append(r)
        term = events[i].terminal
        if term:
            key = (owner, int(i))
            counts[key] = counts.get(key, 0) + 1
            if counts[key] >= term:
                t_stop[owner] = ts
    log = EventLog(
        names=names,
        event=np.array([r[2] for r in kept], dtype=np.int64),
        body=np.array([r[1] for r in kept], dtype=np.int64),
        t=np.array([r[0] for r in kept], dtype=float),
        state=np.array([r[3] for r in kept], dtype=float).reshape(len(kept), d),
        direction=np.array([r[4] for r in kept], dtype=float),
        t_stop=t_stop.reshape(batch) if batch else t_stop.reshape(()),
        batch=batch,
    )
    stopped = np.flatnonzero(np.isfinite(t_stop))
    if stopped.size == 0:
        return t, y, log
    final = {int(b): log.state[(log.body == b) & (log.t == t_stop[b])][-1] for b in stopped}
    if nb == 1 and not batch:
        ts = float(t_stop[0])
        keep = int(np.searchsorted(t, ts, side="left"))
        t_new = np.concatenate([t[:keep], [ts]])
        y_new = np.concatenate([y[:keep], final[0][None, None, :]], axis=0)
        return t_new, y_new, log
    y = y.copy()
    last = float(np.max(np.where(np.isfinite(t_stop), t_stop, t[-1])))
    keep = min(n, int(np.searchsorted(t, last, side="left")) + 1)
    for b, state in final.items():
        y[t > t_stop[b], b] = state
    return t[:keep], y[:keep], log


def solve_dense(
    rhs: Callable[[float, np.ndarray], np.ndarray],
    t0: float,
    t1: float,
    y0: np.ndarray,
) -> Callable[[float], np.ndarray]:
    """DOP853 at ``rtol = 1e-13`` from ``y0`` (N, d) at ``t0`` to ``t1``; ``rhs(t, Y
    (N, d)) -> (N, d)``; returns ``s(t) -> (N, d)`` (the dense output)."""
    from scipy.integrate import solve_ivp

    shape = y0.shape

    def fun(s: float, v: np.ndarray) -> np.ndarray:
        return np.asarray(rhs(s, v.reshape(shape)), dtype=float).reshape(-1)

    sol = solve_ivp(fun, (t0, t1), y0.reshape(-1), method="DOP853", rtol=_RTOL, atol=_ATOL,
                    dense_output=True)  # fmt: skip
    if sol.status != 0:
        raise IntegrationError(
            f"Locating an event between t = {t0:.6g} s and {t1:.6g} s failed: {sol.message}"
        )
    dense = sol.sol

    def at(s: float) -> np.ndarray:
        return np.asarray(dense(s)).reshape(shape)

    return at
