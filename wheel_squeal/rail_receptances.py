"""The rail a design rolls on, as the ``track`` command and the API report it
(``track.receptances``)."""

from __future__ import annotations

from track.receptances import TrackReceptances

from .design import Design
from .model_sections import Track
from .runtime.request_errors import RequestError

__all__ = ["TrackReceptances", "track_receptances"]


def track_receptances(
    design: Design, fmin_hz: float = 20.0, fmax_hz: float = 5000.0, points: int = 300
) -> TrackReceptances:
    """The receptances of the track ``design`` rolls on (its ``[counter_body]`` must be a
    track) at ``points`` frequencies spaced logarithmically from ``fmin_hz`` to ``fmax_hz``
    (``track.receptances.track_receptances``).

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> t = track_receptances(ws.load_design("railway_920_track"), 100.0, 1000.0, 5)
    >>> round(t.pinned_pinned_hz["vertical"])
    1068
    """
    from track.receptances import track_receptances as receptances

    body = design.counter_body
    if not isinstance(body, Track):
        raise RequestError(
            f"{design.name} rolls on a {body.KIND}, not a track: "
            'give a design with [counter_body] kind = "track"'
        )
    try:
        return receptances(body, fmin_hz, fmax_hz, points)
    except ValueError as exc:
        raise RequestError(str(exc)) from None
