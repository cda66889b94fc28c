"""Built-in examples: list them, and load one as a dataset."""

from __future__ import annotations

from fastapi import APIRouter, Request

from .. import examples as ex
from .. import payloads, schemas
from ..errors import NotFound
from .deps import cache, jobs, progress_key

router = APIRouter(prefix="/api/examples", tags=["examples"])


@router.get("", summary="The built-in examples", response_model=list[schemas.Example])
async def list_examples():
    return [{"name": e.name, "title": e.title, "description": e.description, "rows": e.rows, "cols": e.cols}
            for e in ex.catalogue().values()]


@router.post("/{name}", summary="Load a built-in example as a new dataset", response_model=schemas.Dataset)
async def load_example(request: Request, name: str):
    found = ex.catalogue().get(name)
    if found is None:
        raise NotFound(f"No example named {name!r}; the examples are {', '.join(ex.catalogue())}.")
    c = cache(request)

    def work():
        data, geometry = found.build()
        summary = payloads.dataset_summary(data, geometry, found.title, c.settings, {"example": name},
                                           found.rows, found.cols)
        return c.add_dataset(data, geometry, found.title, summary)

    return await jobs(request).heavy(work, progress=progress_key(request), message=f"Preparing {found.title}")
