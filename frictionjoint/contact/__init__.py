"""Contact mechanics that gives joint parameters: Cattaneo-Mindlin microslip (DESIGN.md section 4)."""
from .mindlin import MindlinContact

__all__ = ["MindlinContact"]
