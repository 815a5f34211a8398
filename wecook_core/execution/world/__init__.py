"""The executor's world, simulator-free: the primitives grasp / engage / actuate / place as programs
(generators, see :mod:`wecook_core.execution.schedule.executor`) and the roles calling them, over two protocols.
The PyBullet adapter, :mod:`wecook_core.execution.bullet`, implements the protocols; nothing here imports it
(or pybullet), so the tests run the primitives and roles against a plain-Python fake.

Arms are driven along their trajectories kinematically (joints set every step, motors holding them); objects
are dynamic bodies; a grasped object rides on a fixed constraint to the hand (and is kept exactly on it).
Goals come from TSR samples through re-seeded IK, checked for collisions in the planning client; paths come from
the motion planner (every query time-limited). A goal that fails is retried with new samples, up to
``attempts`` rounds of ``samples`` samples; then the primitive fails with its reason.

Composed, not layered: primitives and roles are written against two small protocols (:mod:`.protocols`), so the
tests run them against a plain-Python fake:

- :mod:`.protocols`: a ``Scene`` (where things are, what the hands hold, stepping, events) and an ``Arm`` (one
  person's arm: goals, planned and straight moves, the gripper, going home);
- :mod:`wecook_core.execution.bullet.scene` (``BulletScene``) and :mod:`~wecook_core.execution.bullet.arm`
  (``BulletArm``): them in PyBullet, the arms sharing a ``Traffic`` (the planner's budget and how they keep out
  of each other's way);
- :mod:`.grasping` (grasp, release), :mod:`.actuating` (engage, actuate), :mod:`.placing` (place), gathered by
  :mod:`.primitives` (``Primitives``), all retried by one policy, :mod:`.retry`;
- :mod:`.roles` (``RolePlayer``): actions and the roles of collaborations;
- :mod:`wecook_core.execution.bullet.world` (``BulletWorld``): the executor's world, putting them together.
"""
