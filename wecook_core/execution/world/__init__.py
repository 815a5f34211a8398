"""The PyBullet world of the executor: a simulating client, a planning client, and the primitives
grasp / engage / actuate / place as programs (generators, see :mod:`wecook_core.execution.executor`).

Arms are driven along their trajectories kinematically (joints set every step, motors holding them); objects
are dynamic bodies; a grasped object rides on a fixed constraint to the hand (and is kept exactly on it).
Goals come from TSR samples through re-seeded IK, checked for collisions in the planning client; paths come from
the motion planner (every query time-limited). A goal that fails is retried with new samples, up to
``attempts`` rounds of ``samples`` samples; then the primitive fails with its reason.

Layers, each a class built on the one below:

- :mod:`.state` (``WorldState``): the two clients, the scene, the hands, the clock, what the observer sees;
- :mod:`.moves` (``ArmMotion``): goals, planned and straight moves, sharing the table between the arms;
- :mod:`.grasping` (``Grasping``): grasp and release; :mod:`.actuating` (``Actuating``): engage and actuate;
  :mod:`.primitives` (``Primitives``): place; all retried by one policy, :mod:`.retry`;
- :mod:`.roles` (``BulletWorld``): actions and the roles of collaborations.
"""

from wecook_core.execution.world.roles import BulletWorld

__all__ = ["BulletWorld"]
