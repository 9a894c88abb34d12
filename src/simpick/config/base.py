"""The building blocks of the config's models: the strict base model (no unknown keys) and the
constrained number types, defined in the lowest layer (:mod:`simpick.params`) so that the stages'
job models and the config's sections share them."""

from __future__ import annotations

from simpick.params import Finite, NonNegative, Positive, Strict

__all__ = ["Finite", "NonNegative", "Positive", "Strict"]
