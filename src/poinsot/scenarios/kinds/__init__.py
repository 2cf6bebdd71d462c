"""Scenario adapters, one module per kind (registered in :mod:`..registry`).

- :mod:`.free_body`: a torque-free rigid body (exact solution or integrators);
- :mod:`.torqued_body`: a rigid body under a constant body or space torque, or
  gravity about a fixed point (the heavy body);
- :mod:`.attitude`: attitude propagated from a prescribed angular velocity;
- :mod:`.coning`: classical coning motion (closed form vs integrators).

The recipe for a new kind is ``docs/adding-a-motion.md``.
"""
