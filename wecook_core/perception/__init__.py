"""Perception: observations -> segments, associations and actions, merged into trees (:mod:`wecook_core.trees`)."""
