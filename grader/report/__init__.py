"""What a TA reads after grading: score tables, the class report, collusion evidence."""
