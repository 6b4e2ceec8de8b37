"""Service settings, read from the environment (prefix ``CAMCORE_``) in one place."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any, Literal

from pydantic import Field, ValidationError, field_validator, model_validator
from pydantic_core import PydanticCustomError
from pydantic_settings import BaseSettings, SettingsConfigDict
from pydantic_settings.exceptions import SettingsError

ENV_PREFIX = "CAMCORE_"
#: uvicorn's log levels (uvicorn.config.LOG_LEVELS)
LogLevel = Literal["critical", "error", "warning", "info", "debug", "trace"]
#: settings whose values are never echoed in an error message
_SECRET_FIELDS = frozenset({"api_key"})


class Settings(BaseSettings):
    """Everything the service can be told from outside; defaults suit local use.

    Every field can be set as an environment variable with the prefix, e.g.
    ``CAMCORE_PORT=9000`` or ``CAMCORE_MAX_TABLE_SAMPLES=50000``.
    """

    model_config = SettingsConfigDict(env_prefix=ENV_PREFIX, extra="ignore")

    host: str = "127.0.0.1"
    port: int = Field(8000, ge=1, le=65535)
    workers: int = Field(1, ge=1, le=64)
    log_level: LogLevel = "info"
    keep_alive_s: int = Field(30, ge=1, le=3600, description="idle keep-alive before the server closes a connection")

    # transport (service/protocol.py): checked as the bytes arrive, before the app or the key check
    max_header_bytes: int = Field(16 * 1024, ge=1024, le=1024 * 1024,
                                  description="request line and headers together; larger is refused with 431")
    max_url_bytes: int = Field(8 * 1024, ge=256, le=64 * 1024, description="request target; longer is refused with 414")
    header_timeout_s: float = Field(10.0, gt=0, le=3600,
                                    description="from connection (or the request's first byte) to the end of its headers; 408")
    body_timeout_s: float = Field(20.0, gt=0, le=3600, description="from the end of the headers to the end of the body; 408")
    write_timeout_s: float = Field(30.0, gt=0, le=3600,
                                   description="an answer the client does not read for this long is dropped (connection reset)")
    max_connections: int = Field(
        128, ge=1, le=100_000,
        description="open connections per worker; a connection accepted past it is answered 503 with Retry-After "
                    "(GET /health is still answered) and closed")

    # limits: larger work is refused with 413 naming the limit
    max_body_bytes: int = Field(4 * 1024 * 1024, ge=1024)
    max_table_samples: int = Field(200_000, ge=2)
    max_inverse_points: int = Field(200_000, ge=1)
    max_bezier_degree: int = Field(20, ge=1)  # degree 20 at 2e5 samples answers in ~0.5 s here
    max_curve_points: int = Field(10_000, ge=2)
    max_motion_segments: int = Field(100, ge=1, description="segments of a motion program; more: 413")
    max_toolpath_elements: int = Field(20_000, ge=1, description="lines and arcs of a toolpath or a solid's contour; "
                                                                 "more: 413")
    max_stl_triangles: int = Field(1_000_000, ge=1, description="facets of an STL solid; more: 413")
    max_sweep_combinations: int = Field(10000, ge=1, description="designs of one sizing sweep; more: 413")
    max_vibration_tau_values: int = Field(10_000, ge=1, description="τ values of a residual-vibration spectrum; more: 413")

    # work (camcore.work estimates it before it runs; service.admission admits it)
    max_work_s: float = Field(1.0, gt=0, le=3600, description="budget: a request estimated to need more is refused (413)")
    work_deadline_s: float = Field(1.5, gt=0, le=3600,
                                   description="a computation not done this long after admission is stopped (503)")
    work_slots: int = Field(2, ge=1, le=64, description="computations running at once per worker (threads)")
    max_queued_work_s: float = Field(2.0, gt=0, le=3600,
                                     description="estimated seconds admitted and not finished per worker; more: 503")
    max_queue_wait_s: float = Field(0.5, gt=0, le=3600,
                                    description="a computation that would wait (or has waited) longer for a slot: 503")
    max_in_flight: int = Field(64, ge=1, le=100_000, description="requests in progress per worker; more: 503")
    inline_work_s: float = Field(0.003, ge=0, le=0.05,
                                 description="a computation estimated at most this long runs on the event loop "
                                             "(no thread, slot or deadline: it costs less than they do)")
    max_answer_bytes_in_flight: int = Field(
        64 * 1024 * 1024, ge=1024 * 1024, le=1 << 40,
        description="bytes of answers one worker holds for its open downloads; an answer that would pass it: 503 "
                    "(one answer alone may pass it)")

    # the CAD kernel (STEP, STL) in processes of its own, per worker (service/cad_pool.py)
    cad_processes: int = Field(1, ge=1, le=16, description="kernel processes per worker (solids written at once)")
    cad_max_tasks: int = Field(50, ge=1, le=100_000, description="solids a kernel process writes before it is replaced")
    cad_idle_s: float = Field(60.0, gt=0, le=86_400,
                              description="a kernel process without a solid this long exits (its memory goes back)")

    # caches: bounded by entry count; tables are cached only up to a row count
    curve_cache_size: int = Field(512, ge=0)
    curve_cache_max_bytes: int = Field(64 * 1024 * 1024, ge=0)
    table_cache_size: int = Field(256, ge=0)
    table_cache_max_rows: int = Field(10_001, ge=0)
    table_cache_max_bytes: int = Field(32 * 1024 * 1024, ge=0)
    profile_checks_cache_size: int = Field(256, ge=0)
    sizing_cache_size: int = Field(256, ge=0)
    reply_cache_size: int = Field(256, ge=0)

    # access control (off by default for local use)
    api_key: str | None = None
    api_key_file: Path | None = Field(None, description="a file holding the API key (a mounted Secret); its "
                                                        "text, without the trailing newline, becomes api_key")
    cors_origins: list[str] = Field(default_factory=list)

    @field_validator("log_level", mode="before")
    @classmethod
    def _lower_case_level(cls, value: Any) -> Any:
        return value.lower() if isinstance(value, str) else value

    @field_validator("api_key_file")
    @classmethod
    def _key_file_holds_a_key(cls, path: Path | None) -> Path | None:
        if path is not None:
            _read_key(path)
        return path

    @model_validator(mode="after")
    def _key_from_file(self) -> Settings:
        # a key in a file (Kubernetes mounts a Secret's key as one) is in no environment
        # variable, which `ps e`, /proc/<pid>/environ or a child process could show
        if self.api_key_file is not None:
            if self.api_key:
                raise PydanticCustomError("key_twice", "CAMCORE_API_KEY and CAMCORE_API_KEY_FILE are both set: "
                                                       "set one")
            self.api_key = _read_key(self.api_key_file)
        return self


def _read_key(path: Path) -> str:
    """The key a file holds: its text without the trailing newline (`echo key > file` adds one)."""
    try:
        key = path.read_text(encoding="utf-8").rstrip("\r\n")
    except OSError as exc:
        raise PydanticCustomError("key_file", "cannot be read: {reason}", {"reason": exc.strerror}) from None
    except UnicodeDecodeError:
        raise PydanticCustomError("key_file", "is not UTF-8 text") from None
    if not key.strip():
        raise PydanticCustomError("key_file", "is empty")
    return key


def environment_name(field: str) -> str:
    return f"{ENV_PREFIX}{field.upper()}"


def _shown(field: str, value: Any) -> str:
    if field in _SECRET_FIELDS:
        return ""
    text = repr(value) if isinstance(value, str) else str(value)
    return "=" + (text if len(text) <= 60 else text[:57] + "...")


def settings_error_line(exc: ValidationError | SettingsError) -> str:
    """One line naming each bad environment variable and what it allows, e.g.
    ``CAMCORE_WORKERS=0 must be greater than or equal to 1``."""
    if isinstance(exc, SettingsError):  # a complex value (a list) that is not JSON
        match = re.search(r'field "(\w+)"', str(exc))
        name = environment_name(match.group(1)) if match else "a CAMCORE_ variable"
        cause = f" ({exc.__cause__})" if exc.__cause__ else ""
        return f"{name} must be a JSON list, e.g. '[\"https://app.example\"]'{cause}"
    parts = []
    for error in exc.errors():
        field = str(error["loc"][0]) if error["loc"] else ""
        name = environment_name(field) if field else "the settings"
        msg = error["msg"].replace("Input should be", "must be", 1)
        parts.append(f"{name}{_shown(field, error.get('input')) if field else ''} {msg}")
    return "; ".join(parts)
