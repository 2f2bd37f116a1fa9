"""Grades and feedback in the formats other systems read: Canvas, Moodle, nbgrader's feedback folder."""
