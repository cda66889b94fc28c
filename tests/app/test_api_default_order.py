"""The order an analysis keeps when it names none (app/limits.py, era's DEFAULT_MAX_ORDER): the leading triplets, by
the truncated SVD when that is far below H(0)'s size, and a clear refusal above them; the order it opens at."""

from __future__ import annotations

import numpy as np

from app.limits import DEFAULT_MAX_ORDER

from apiclient import client


def test_the_grid_example_keeps_200_orders_by_the_truncated_svd_and_says_how_to_get_more(tmp_path):
    with client(tmp_path) as c:
        ds = c.post("/api/examples/grid").json()
        rows, cols = ds["defaults"]["rows"], ds["defaults"]["cols"]
        a = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": rows, "cols": cols}).json()
        assert a["max_order"] == DEFAULT_MAX_ORDER == ds["defaults"]["max_order"]
        assert a["requested_max_order"] is None and a["svd_method"] == "truncated"
        # the whole spectrum is still there for the plot and the suggestion (a dense SVD gives the same)
        d = np.array(a["singular_values"])
        assert d.size == 2 * DEFAULT_MAX_ORDER and np.all(np.diff(d) <= 0) and a["noise_floor_order"] == 30
        # the order the page opens at is the automatic choice's, one of the diagram's orders (2 … 160)
        stab = c.get(f"/api/analyses/{a['id']}/stabilization").json()
        assert a["suggested_order"] == stab["chosen_order"] and a["suggested_order"] in stab["orders"]
        assert stab["orders"][-1] == 160 and a["chosen_indices"] == stab["chosen_indices"]
        above_diagram = c.get(f"/api/analyses/{a['id']}/modes", params={"order": 180, "fit": False})
        assert above_diagram.status_code == 200 and above_diagram.json()["order"] == 180
        r = c.get(f"/api/analyses/{a['id']}/modes", params={"order": DEFAULT_MAX_ORDER + 2})
        assert r.status_code == 422
        assert "max_order, 200" in r.text and "larger max_order" in r.text
        # asking for more gives more (the dense SVD: 400 is above a third of 792)
        more = c.post("/api/analyses", json={"dataset_id": ds["id"], "rows": rows, "cols": cols,
                                             "max_order": 400}).json()
        assert more["max_order"] == 400 and more["svd_method"] == "dense"
        np.testing.assert_allclose(more["singular_values"][:400], d, rtol=1e-6)
