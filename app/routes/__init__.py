"""One router per resource: datasets, examples, analyses, reports, pages."""
