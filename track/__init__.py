"""What the wheel runs on: a rail on discrete, periodic supports and its receptances at the
contact, the rig's roller, profiles and curving (the physics layer).

- :mod:`track.design_sections`: the design file's sections of what the wheel rolls on
  (``[counter_body]``: the roller or a track) and of the bogie in curves (``[vehicle]``).
- :mod:`track.beam`: the rail as a Timoshenko beam on pads, sleepers and ballast (or a
  continuous support) and its point receptance; the closed forms it must meet.
- :mod:`track.fit`: a receptance as a sum of passive modal terms (mass, spring and damper
  each), the form the squeal model's counter-body takes.
- :mod:`contact.profiles`: the S1002 wheel and UIC60 rail heads from their standards, a cone,
  any profile from points.
- :mod:`contact.wheel_rail`: where a wheelset's wheels touch their rails at each lateral
  shift (rolling radii, contact angles, curvatures, the flange's contact).
- :mod:`track.curving`: a curve's kinematics and the curves it refuses;
  :mod:`track.bogie_curving`: a bogie's steady curving, each wheel at its own contact.
"""

from __future__ import annotations

from .beam import BeamSection, Supports, continuous_receptance, pinned_pinned_frequency_hz, receptance

__all__ = [
    "TEST_TRACK_LATERAL",
    "TEST_TRACK_VERTICAL",
    "UIC60_LATERAL",
    "UIC60_VERTICAL",
    "BeamSection",
    "Supports",
    "continuous_receptance",
    "pinned_pinned_frequency_hz",
    "receptance",
]

#: UIC60 rail bending vertically (E 210 GPa, G 81 GPa, 7850 kg/m^3, A 76.7 cm^2,
#: I 3038.3 cm^4, kappa 0.4) and laterally (I 512.7 cm^4, kappa 0.538); loss factor 0.01
UIC60_VERTICAL = BeamSection(210e9, 81e9, 7850.0, 76.7e-4, 3038.3e-8, 0.4, 0.01)
UIC60_LATERAL = BeamSection(210e9, 81e9, 7850.0, 76.7e-4, 512.7e-8, 0.538, 0.01)
#: The test track's supports: sleepers every 0.6 m, 162 kg per rail seat; pads 300 MN/m
#: (loss factor 0.25) on ballast 50 MN/m (1.0) vertically, 50 MN/m (0.25) on 35 MN/m (1.0)
#: laterally
TEST_TRACK_VERTICAL = Supports(0.6, 300e6, 0.25, 162.0, 50e6, 1.0)
TEST_TRACK_LATERAL = Supports(0.6, 50e6, 0.25, 162.0, 35e6, 1.0)
