"""The model protocol explain relies on (era.discrepancy.protocol.ExplainModel), checked statically: mypy on
era/discrepancy is clean (its config in pyproject.toml [tool.mypy]), and the NASA grid's model, an era.Frame's
model and a matrix model's satisfy the protocol, while a model that lacks part of it is caught."""

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

CONFORMS = '''
from era.discrepancy.frame_model import FrameModel
from era.discrepancy.matrix_model import MatrixExplainModel
from era.discrepancy.protocol import ExplainModel, Modes, RitzModes
from era.examples.frames import portal
from era.examples.grid import nasa_grid
from era.models import MatrixModel

grid: ExplainModel = nasa_grid()
frame: ExplainModel = FrameModel.of(portal())
matrices: ExplainModel = MatrixExplainModel.of(MatrixModel([[1.0]], [[1.0]], [("1", "x")]), [("1", "x")])
approx: Modes = RitzModes(*(3 * [None]))  # type: ignore[arg-type]
'''

LACKS_RITZ = '''
import numpy as np
from era.discrepancy.protocol import ExplainModel

class NoRitz:
    params: dict = {}
    sensors: tuple = ()
    joints_ft = np.zeros((0, 2))
    node_labels: tuple = ()
    has_ritz = False
    default_member_scatter = 0.0
    exact: "NoRitz"
    def with_params(self, **changes) -> "NoRitz": return self
    def modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]: return np.zeros(0), np.zeros((0, 0))
    def node_modes(self, n_modes: int = 10) -> tuple[np.ndarray, np.ndarray]: return np.zeros(0), np.zeros((0, 0))

model: ExplainModel = NoRitz()
'''


def _mypy(tmp_path: Path, *targets: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "mypy", "--cache-dir", str(tmp_path / "cache"), *targets],
                          cwd=ROOT, capture_output=True, text=True, timeout=900)


def test_mypy_on_era_discrepancy_is_clean_and_both_models_implement_the_protocol(tmp_path):
    snippet = tmp_path / "conforms.py"
    snippet.write_text(CONFORMS)
    done = _mypy(tmp_path, "era/discrepancy", str(snippet))
    assert done.returncode == 0, done.stdout + done.stderr
    assert "Success: no issues found" in done.stdout


def test_a_model_without_the_whole_protocol_is_caught(tmp_path):
    snippet = tmp_path / "lacks_ritz.py"
    snippet.write_text(LACKS_RITZ)
    done = _mypy(tmp_path, str(snippet))
    assert done.returncode == 1, done.stdout + done.stderr
    assert 'expression has type "NoRitz", variable has type "ExplainModel"' in done.stdout
