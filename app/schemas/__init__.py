"""The JSON contract of the API: one pydantic model per answer, declared on every route (see /docs), and the
request bodies beside the answers they ask for, one module per resource.

NaN and ±inf are not JSON: every float the server cannot give is sent as null, so float lists are
``list[float | None]``. Shapes in the descriptions: p outputs, m inputs, k modes, N samples. Answers are built
as plain dicts in app/payloads.py; tests/app/test_schemas.py checks that they carry exactly these fields.
Every public name is re-exported here: ``from app.schemas import Dataset`` and ``schemas.Dataset`` work.
"""

from .common import MAX_INT, Error, Floats, Index, Matrix, Schema
from .datasets import (
    Dataset, DatasetLimits, DatasetSource, Example, GeometrySummary, HankelDefaults, Records, Spectrum,
)
from .imports import Import, ImportChannel, ImportOptions, ImportPreview
from .analyses import (
    Analysis, AnalysisRequest, ChoiceCandidate, Modes, Reconstruction, Stabilization, StableMode, Step, ViewerLink,
    ViewerRequest,
)
from .explain import (
    ExplainBasis, ExplainRequest, ExplainViewerRequest, Explained, ExplainedMode, Explanation, ExplanationOverlay,
    Gap, LocatedEvidence, NamedEffect, Overlay, Place, RankedEffect, RejectedTrial, UsedModel,
)
from .reports import (
    FrozenModel, OfflineReport, Report, ReportCreated, ReportDocument, ReportGeometry, ReportPair,
    ReportReconstruction, ReportRequest,
)
from .campaigns import (
    Campaign, CampaignAnalysis, CampaignFailure, CampaignFolder, CampaignFolders, CampaignMode, CampaignRecord,
    CampaignResult, CampaignSeries,
)
from .models import (BestPartner, MappingRequest, ModelComparison, ModelDraft, ModelRequest, ModelView, ModelViewLink,
                     PointMatch, StructureModel)
from .jobs import Progress
from .health import Health, StoreUsage

__all__ = [
    "MAX_INT", "Error", "Floats", "Index", "Matrix", "Schema", "Dataset", "DatasetLimits", "DatasetSource",
    "Example", "GeometrySummary", "HankelDefaults", "Records", "Spectrum", "Import", "ImportChannel",
    "ImportOptions", "ImportPreview", "Analysis", "AnalysisRequest", "ChoiceCandidate", "Modes", "Reconstruction",
    "Stabilization", "StableMode", "Step", "ViewerLink", "ViewerRequest", "ExplainBasis", "ExplainRequest",
    "ExplainViewerRequest", "Explained", "ExplainedMode", "Explanation", "ExplanationOverlay", "Gap",
    "LocatedEvidence", "NamedEffect", "Overlay", "Place", "RankedEffect", "RejectedTrial", "UsedModel",
    "FrozenModel", "OfflineReport", "Report", "ReportCreated", "ReportDocument", "ReportGeometry", "ReportPair",
    "ReportReconstruction", "ReportRequest", "Campaign", "CampaignAnalysis", "CampaignFailure", "CampaignFolder",
    "CampaignFolders", "CampaignMode", "CampaignRecord", "CampaignResult", "CampaignSeries", "BestPartner",
    "ModelComparison", "MappingRequest", "PointMatch", "ModelDraft", "ModelRequest", "ModelView", "ModelViewLink",
    "StructureModel", "Progress", "Health", "StoreUsage"
]
