"""Perception: observations -> segments, associations and actions, merged into trees (:mod:`wecook_core.trees`).

Every rule the stages apply, with its source (the paper's section or the physical cue), the failure it fixed,
its parameters and the test that pins it: ``wecook_core/perception/RULES.md``.
"""
