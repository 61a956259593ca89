"""The three tasks a macro is started with, in the order the protocol numbers them (docs/protocol.md,
START's ``task``), and how each is named to a user."""
from __future__ import annotations

from ..i18n import N_

TASKS = ("charge", "discharge", "train")
# How a task is named: as a choice (a combo box item) and within a sentence.
TASK_LABELS = {"charge": N_("Charge"), "discharge": N_("Discharge"), "train": N_("Train")}
TASK_WORDS = {"charge": N_("charge"), "discharge": N_("discharge"), "train": N_("train")}
