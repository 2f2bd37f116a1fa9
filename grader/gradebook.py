"""nbgrader's gradebook entries of an assignment, written by nbgrader itself: shared by building and grading."""

from __future__ import annotations

from grader.paths import COURSE_ID, CoursePaths


class GradebookError(RuntimeError):
    """nbgrader could not generate the assignment (its log is in the message)."""


def generate_assignment(paths: CoursePaths, assignment: str, db_url: str | None = None) -> None:
    """Run nbgrader's own ``generate_assignment`` (release notebooks + gradebook entries)."""
    from nbgrader.apps import NbGraderAPI
    from nbgrader.coursedir import CourseDirectory
    from traitlets.config import Config

    config = Config()
    config.CourseDirectory.root = str(paths.course)
    config.CourseDirectory.db_url = db_url or paths.gradebook_url
    config.CourseDirectory.course_id = COURSE_ID
    api = NbGraderAPI(coursedir=CourseDirectory(config=config), config=config)
    result = api.generate_assignment(assignment, force=True, create=True)
    if not result.get("success"):
        log = (result.get("log") or "")[-4000:]
        raise GradebookError(f"nbgrader generate_assignment failed:\n{log}\n{(result.get('error') or '')[-2000:]}")
