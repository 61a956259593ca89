"""The foundations of the window, below every other ui package."""
