"""The app's own error: an unknown id (404). Everything else the person can fix is an era.EraError (422)."""


class NotFound(LookupError):
    """An unknown dataset, analysis, report, example or progress key (404); the message says what to do."""
