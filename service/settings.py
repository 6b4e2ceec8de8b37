"""Service settings, read from the environment (prefix ``CAMCORE_``) in one place."""

from __future__ import annotations

from pydantic import Field
from pydantic_settings import BaseSettings, SettingsConfigDict


class Settings(BaseSettings):
    """Everything the service can be told from outside; defaults suit local use.

    Every field can be set as an environment variable with the prefix, e.g.
    ``CAMCORE_PORT=9000`` or ``CAMCORE_MAX_TABLE_SAMPLES=50000``.
    """

    model_config = SettingsConfigDict(env_prefix="CAMCORE_", extra="ignore")

    host: str = "127.0.0.1"
    port: int = Field(8000, ge=1, le=65535)
    workers: int = Field(1, ge=1, le=64)
    log_level: str = "info"
    keep_alive_s: int = Field(30, ge=1, le=3600, description="idle keep-alive before the server closes a connection")

    # limits: larger work is refused with 413 naming the limit
    max_body_bytes: int = Field(4 * 1024 * 1024, ge=1024)
    max_table_samples: int = Field(200_000, ge=2)
    max_inverse_points: int = Field(200_000, ge=1)
    max_bezier_degree: int = Field(20, ge=1)  # degree 20 at 2e5 samples answers in ~0.5 s here
    max_curve_points: int = Field(10_000, ge=2)

    # work (camcore.work estimates it before it runs; service.admission admits it)
    max_work_s: float = Field(1.0, gt=0, le=3600, description="budget: a request estimated to need more is refused (413)")
    work_deadline_s: float = Field(2.0, gt=0, le=3600, description="a computation still running after this is stopped (503)")
    work_slots: int = Field(2, ge=1, le=64, description="computations running at once per worker (threads)")
    max_queued_work_s: float = Field(2.0, gt=0, le=3600,
                                     description="estimated seconds admitted and not finished per worker; more: 503")
    max_in_flight: int = Field(64, ge=1, le=100_000, description="requests in progress per worker; more: 503")

    # caches: bounded by entry count; tables are cached only up to a row count
    curve_cache_size: int = Field(512, ge=0)
    curve_cache_max_bytes: int = Field(64 * 1024 * 1024, ge=0)
    table_cache_size: int = Field(256, ge=0)
    table_cache_max_rows: int = Field(10_001, ge=0)
    table_cache_max_bytes: int = Field(32 * 1024 * 1024, ge=0)

    # access control (off by default for local use)
    api_key: str | None = None
    cors_origins: list[str] = Field(default_factory=list)
