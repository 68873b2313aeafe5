"""Where the wheel meets the rail or the roller (the physics layer, below the squeal
model and the track):

- :mod:`contact.hertz`: the Hertz contact (ellipse, pressure, approach) and Kalker's creep
  coefficients;
- :mod:`contact.creep`: the creep law of Liu & Meehan (CM2015) and the friction laws by
  registry (``FRICTION_LAWS``: one class gives the falling factor, its slope and the
  compiled kernels' parameters);
- :mod:`contact.frames`: a contact's frame on the wheel's running surface (its point,
  normal and angle);
- :mod:`contact.profiles`: wheel and rail profiles (S1002, UIC60 and the design's own);
- :mod:`contact.wheel_rail`: where a wheelset's wheels touch their rails at each lateral
  shift (rolling radii, contact angles, curvatures, the flange's contact);
- :mod:`contact.numerics`: a bracketed root and the complete elliptic integrals.
"""
