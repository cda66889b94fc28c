"""Built-in examples: the paper's Case I and Case II, and a simulated test of the NASA grid, each with the Hankel
size the paper or the test suggests."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import era
from era.examples import paper_cases
from era.examples.grid import nasa_grid
from era.examples.grid_simulation import simulate_grid_test


@dataclass(frozen=True)
class Example:
    name: str
    title: str
    description: str
    build: Callable[[], tuple]  # () -> (ResponseData, Geometry | None)
    rows: int | None = None
    cols: int | None = None


def _case_1():
    return paper_cases.case_1(200), None


def _case_2():
    return paper_cases.case_2(200, mimo=True), None


def _grid():
    # The hidden effect is what the simulation-vs-test issue asks people to find; the app only shows the data.
    data, _truth = simulate_grid_test(effect="point_mass", seed=7)
    return data, nasa_grid().geometry()


def catalogue() -> dict[str, Example]:
    return {
        "case1": Example("case1", "Paper Case I: five modes, one sensor",
                         "Juang & Pappa 1985, eqs. 58-60: free decay of five modes (s = -0.01j + ij rad/s) "
                         "seen by one sensor, Δτ = 0.05 s, 200 samples.", _case_1, 90, 90),
        "case2": Example("case2", "Paper Case II: a repeated pair, 2 × 2",
                         "Juang & Pappa 1985, eqs. 64-67: the pair -0.01 ± i appears twice; two sensors and "
                         "two initial conditions (MIMO) separate both copies.", _case_2, 45, 45),
        "grid": Example("grid", "NASA 7 ft × 10 ft grid: simulated test",
                        "The paper's grid with its nine sensors: simulated impact test of the finite-element "
                        "model with a hidden effect, noise included, and the grid geometry for mode shapes.", _grid),
    }
