"""A thread-safe map that keeps only the newest keys: the viewer's published scenes and pick scenes."""

from __future__ import annotations

import threading
from collections import OrderedDict


class Recent:
    """key -> item behind one lock (FastAPI threads write, viser's threads read); the newest ``capacity`` keys are
    kept, the oldest dropped first."""

    def __init__(self, capacity: int):
        self.capacity = capacity
        self._items: OrderedDict = OrderedDict()
        self._lock = threading.Lock()

    def _put(self, key: str, item) -> str:
        with self._lock:
            self._items[key] = item
            while len(self._items) > self.capacity:
                self._items.popitem(last=False)
        return key

    def __contains__(self, key: str) -> bool:
        with self._lock:
            return key in self._items
