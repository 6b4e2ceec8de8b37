"""The service's bridge to camcore.profile.dynamics: a request in, the table and summary out."""

from __future__ import annotations

import math
from typing import Any

from fastapi import Request

from camcore.errors import GeometryError, NonFiniteResultError
from camcore.profile.dynamics import FollowerDynamics, follower_dynamics
from camcore.results import as_dict
from camcore.work import WorkEstimate, WorkTerm, dynamics_work
from service.errors import within
from service.profiles.dynamics_specs import DynamicsRequest
from service.profiles.service import ProfileService
from service.responses import encode_cost

#: columns of the table: angle, time, lift, velocity, acceleration, spring, contact, normal, torque,
#: and stress (roller) or the pivot torque (oscillating)
COLUMNS = 11


class DynamicsService:
    """Follower dynamics on the cams that :class:`ProfileService` builds (same caches and limits)."""

    def __init__(self, profiles: ProfileService):
        self.profiles = profiles

    def work(self, body: DynamicsRequest, csv: bool) -> WorkEstimate:
        """The curves to build, the extremes over the turn, the rows and their encoding; 413 first
        for more rows than max_table_samples."""
        self.check_samples(body.samples)
        laws, work = self.profiles.laws(body.profile)
        work += dynamics_work(laws, body.samples, self.profiles._schedule_field(body.profile), ("samples",))
        return work + WorkEstimate((WorkTerm(("samples",), f"encoding {body.samples} rows",
                                             encode_cost(body.samples * COLUMNS, csv)),))

    def check_samples(self, samples: int) -> None:
        curves = self.profiles.curves
        curves.check_limit("dynamics samples", samples, curves.settings.max_table_samples, ("samples",))

    def compute(self, body: DynamicsRequest) -> FollowerDynamics:
        self.check_samples(body.samples)
        cam = self.profiles.cam(body.profile)
        roller = None if body.roller is None else body.roller.core()
        # what the cam turns out to be (an impact in its lift, a roller that undercuts it) is about the profile
        with within("profile", only=GeometryError):
            return follower_dynamics(cam, body.load(), body.speed_rpm, body.samples,
                                     safety_margin_n=body.safety_margin_n, roller=roller)

    def answer(self, body: DynamicsRequest) -> tuple[dict[str, Any], dict[str, Any]]:
        """The columns, and the rest of the answer: unit and summary (refused when not finite)."""
        result = self.compute(body)
        summary = as_dict(result.summary)
        for name, value in summary.items():
            if isinstance(value, float) and not math.isfinite(value):
                raise NonFiniteResultError(f"the computation of 'summary.{name}' produced a non-finite number for "
                                           "these inputs; check that they describe a realistic cam and follower.")
        return result.table.columns(), {"unit": result.unit, "summary": summary}


def dynamics_service(request: Request) -> DynamicsService:
    """The app's DynamicsService, built on first use from the ProfileService on ``app.state``."""
    state = request.app.state
    service: DynamicsService | None = getattr(state, "dynamics_service", None)
    if service is None:
        service = DynamicsService(state.profile_service)
        state.dynamics_service = service
    return service
