"""Fixtures of the grader tests: a fake exercise, its solution and the hostile corpus."""
