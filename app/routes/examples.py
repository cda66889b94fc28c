"""Built-in examples: list them, and load one as a dataset."""

from __future__ import annotations

from fastapi import APIRouter, Request

from .. import examples as ex
from ..engine import NotFound
from .deps import engine, jobs, progress_key

router = APIRouter(prefix="/api/examples", tags=["examples"])


@router.get("", summary="The built-in examples")
async def list_examples():
    return [{"name": e.name, "title": e.title, "description": e.description, "rows": e.rows, "cols": e.cols}
            for e in ex.available().values()]


@router.post("/{name}", summary="Load a built-in example as a new dataset")
async def load_example(request: Request, name: str):
    found = ex.available().get(name)
    if found is None:
        raise NotFound(f"No example named {name!r}; the examples are {', '.join(ex.available())}.")

    def work():
        data, geometry = found.build()
        return engine(request).add_dataset(data, geometry, found.title, {"example": name}, found.rows, found.cols)

    return await jobs(request).heavy(work, progress=progress_key(request), message=f"Preparing {found.title}")
