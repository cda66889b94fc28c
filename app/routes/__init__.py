"""One router per resource: datasets, examples, analyses, explain (simulation vs test), reports, jobs, health, pages."""
