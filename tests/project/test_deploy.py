"""deploy/: the Kubernetes manifests and the compose file.

Every manifest is validated (strict: unknown fields are errors) with kubernetes-validate against
the Kubernetes API schemas it bundles, for every version from 1.30 to the newest it has
(1.37 with kubernetes-validate 1.37.0); the compose file against the Compose Specification's
JSON schema that check-jsonschema vendors (``--builtin-schema vendor.compose-spec``). Both
validators work offline. Then the cross-checks no schema makes: probes on the app's health
route, one port everywhere (Dockerfile EXPOSE, CAMCORE_PORT, containerPort, compose mapping),
the image's user, a writable /tmp for matplotlib, resources sized from docs/robustness.md.
"""

from __future__ import annotations

import copy
import json
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path
from typing import Any

import httpx
import kubernetes_validate
import pytest
import yaml
from kubernetes_validate.utils import all_versions

from tests import dockerfile_instructions as df

ROOT = Path(__file__).resolve().parents[2]
DEPLOY = ROOT / "deploy"
K8S_FILES = sorted((DEPLOY / "kubernetes").glob("*.yaml"))
COMPOSE_FILE = DEPLOY / "compose.yaml"
K8S_VERSIONS = sorted({v for v in all_versions() if tuple(map(int, v.split(".")[:2])) >= (1, 30)},
                      key=lambda v: tuple(map(int, v.split("."))))
VERSION = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]["version"]

# docs/robustness.md, memory of one worker: flat at ~185-192 MiB once the bounded caches are full
# (long load runs), 382 MiB the worst ever seen (a run before two caches were cut back)
WORKER_PLATEAU_MIB = 192
WORKER_WORST_MIB = 382


def k8s_documents() -> list[dict[str, Any]]:
    return [doc for path in K8S_FILES for doc in yaml.safe_load_all(path.read_text(encoding="utf-8")) if doc]


def one(kind: str) -> dict[str, Any]:
    (doc,) = [d for d in k8s_documents() if d["kind"] == kind]
    return doc


def container() -> dict[str, Any]:
    (c,) = one("Deployment")["spec"]["template"]["spec"]["containers"]
    return c


def container_env() -> dict[str, str]:
    return {e["name"]: e["value"] for e in container()["env"] if "value" in e}


def health_path() -> str:
    """The app's health route, from the committed OpenAPI document (a drift test keeps it the app's)."""
    document = json.loads((ROOT / "openapi" / "openapi.json").read_text(encoding="utf-8"))
    (path,) = [p for p, ops in document["paths"].items() if ops.get("get", {}).get("operationId") == "getHealth"]
    return path


def mib(quantity: str) -> float:
    """A Kubernetes or compose memory quantity in MiB (256Mi, 1Gi, 1g, 512M, bytes)."""
    m = re.fullmatch(r"(\d+(?:\.\d+)?)\s*([KMGT]i?|[kmgt]b?|)", str(quantity))
    assert m, quantity
    number, unit = float(m.group(1)), m.group(2)
    binary = {"": 1, "Ki": 2**10, "Mi": 2**20, "Gi": 2**30, "Ti": 2**40}
    decimal = {"K": 1e3, "M": 1e6, "G": 1e9, "T": 1e12}
    # compose's units (k, m, g, kb, mb, gb) are binary, as Docker reads them
    compose = {"k": 2**10, "m": 2**20, "g": 2**30, "t": 2**40, "kb": 2**10, "mb": 2**20, "gb": 2**30, "tb": 2**40}
    factor = binary.get(unit) or decimal.get(unit) or compose[unit]
    return number * factor / 2**20


def cores(quantity: str) -> float:
    q = str(quantity)
    return int(q[:-1]) / 1000 if q.endswith("m") else float(q)


@pytest.mark.parametrize("version", K8S_VERSIONS)
def test_manifests_are_valid_kubernetes(version: str) -> None:
    docs = k8s_documents()
    assert {(d["apiVersion"], d["kind"]) for d in docs} == {
        ("apps/v1", "Deployment"), ("v1", "Service"), ("autoscaling/v2", "HorizontalPodAutoscaler"),
        ("policy/v1", "PodDisruptionBudget"), ("networking.k8s.io/v1", "NetworkPolicy")}
    for doc in docs:
        kubernetes_validate.validate(doc, version, strict=True)


def test_the_validator_rejects_a_broken_manifest() -> None:
    # a misspelled field and a wrong type: a validator that passes these checks nothing
    broken = copy.deepcopy(one("Deployment"))
    broken["spec"]["template"]["spec"]["containers"][0]["readinessProbe"]["httpGet"]["pth"] = "/health"
    with pytest.raises(kubernetes_validate.ValidationError):
        kubernetes_validate.validate(broken, K8S_VERSIONS[-1], strict=True)
    broken = copy.deepcopy(one("Deployment"))
    broken["spec"]["template"]["spec"]["automountServiceAccountToken"] = "no"
    with pytest.raises(kubernetes_validate.ValidationError):
        kubernetes_validate.validate(broken, K8S_VERSIONS[-1], strict=True)


def test_probes_ask_the_health_route_on_the_served_port() -> None:
    c = container()
    ports = {p["name"]: p["containerPort"] for p in c["ports"]}
    (exposed,) = df.exposed_ports()
    assert ports == {"http": exposed}
    assert int(container_env()["CAMCORE_PORT"]) == exposed
    for probe in ("startupProbe", "readinessProbe", "livenessProbe"):
        get = c[probe]["httpGet"]
        assert get["path"] == health_path(), probe
        assert ports.get(get["port"], get["port"]) == exposed, probe
    ready, live = c["readinessProbe"], c["livenessProbe"]
    # a busy pod leaves the Service before it is restarted, never the other way round
    assert live["periodSeconds"] * live["failureThreshold"] > ready["periodSeconds"] * ready["failureThreshold"]
    assert live["timeoutSeconds"] >= ready["timeoutSeconds"]


def test_service_and_autoscaler_point_at_the_deployment() -> None:
    deployment, service, hpa = one("Deployment"), one("Service"), one("HorizontalPodAutoscaler")
    pod_labels = deployment["spec"]["template"]["metadata"]["labels"]
    assert deployment["spec"]["selector"]["matchLabels"].items() <= pod_labels.items()
    assert service["spec"]["selector"].items() <= pod_labels.items()
    (port,) = service["spec"]["ports"]
    assert port["targetPort"] in {p["name"] for p in container()["ports"]}
    target = hpa["spec"]["scaleTargetRef"]
    assert (target["apiVersion"], target["kind"], target["name"]) == ("apps/v1", "Deployment",
                                                                      deployment["metadata"]["name"])
    (metric,) = hpa["spec"]["metrics"]
    assert metric["resource"]["name"] == "cpu" and metric["resource"]["target"]["type"] == "Utilization"
    assert 2 <= hpa["spec"]["minReplicas"] <= hpa["spec"]["maxReplicas"]


def test_the_autoscaler_alone_owns_the_replica_count() -> None:
    # a Deployment's spec.replicas is applied as written: with a count in the file, every
    # `kubectl apply` sets a Deployment the HPA scaled out back to that count (the Kubernetes
    # documentation, "Migrating Deployments and StatefulSets to horizontal autoscaling":
    # https://kubernetes.io/docs/tasks/run-application/horizontal-pod-autoscale/#migrating-deployments-and-statefulsets-to-horizontal-autoscaling)
    assert "replicas" not in one("Deployment")["spec"]


def test_disruptions_and_spread_keep_replicas_answering() -> None:
    deployment, pdb, hpa = one("Deployment"), one("PodDisruptionBudget"), one("HorizontalPodAutoscaler")
    pod_labels = deployment["spec"]["template"]["metadata"]["labels"]
    # a drain evicts one pod at a time, and the HPA's floor leaves at least one answering meanwhile
    assert pdb["spec"]["selector"]["matchLabels"].items() <= pod_labels.items()
    assert pdb["spec"]["maxUnavailable"] == 1 and "minAvailable" not in pdb["spec"]
    assert hpa["spec"]["minReplicas"] - pdb["spec"]["maxUnavailable"] >= 1
    # replicas spread over nodes and zones, never left unscheduled for it (ScheduleAnyway)
    spread = {c["topologyKey"]: c for c in deployment["spec"]["template"]["spec"]["topologySpreadConstraints"]}
    assert set(spread) == {"kubernetes.io/hostname", "topology.kubernetes.io/zone"}
    for constraint in spread.values():
        assert constraint["labelSelector"]["matchLabels"].items() <= pod_labels.items()
        assert constraint["maxSkew"] == 1 and constraint["whenUnsatisfiable"] == "ScheduleAnyway"
        assert constraint["matchLabelKeys"] == ["pod-template-hash"]


def test_network_policy_admits_the_http_port_only() -> None:
    policy, deployment = one("NetworkPolicy"), one("Deployment")
    assert policy["spec"]["podSelector"]["matchLabels"].items() <= \
        deployment["spec"]["template"]["metadata"]["labels"].items()
    assert policy["spec"]["policyTypes"] == ["Ingress"]
    (rule,) = policy["spec"]["ingress"]
    assert rule["ports"] == [{"port": "http", "protocol": "TCP"}]
    # the Service's target port is that same named port
    (service_port,) = one("Service")["spec"]["ports"]
    assert service_port["targetPort"] == "http" and "http" in {p["name"] for p in container()["ports"]}


def test_api_key_is_a_mounted_secret_file_and_no_token_is_mounted() -> None:
    from service.settings import Settings

    pod = one("Deployment")["spec"]["template"]["spec"]
    c = container()
    assert pod["automountServiceAccountToken"] is False
    assert not [e for e in c["env"] if "valueFrom" in e], "no Secret in an environment variable"
    assert "CAMCORE_API_KEY" not in {e["name"] for e in c["env"]}
    key_file = Path(container_env()["CAMCORE_API_KEY_FILE"])
    volumes = {v["name"]: v for v in pod["volumes"]}
    (mount,) = [m for m in c["volumeMounts"] if key_file.parent == Path(m["mountPath"])]
    assert mount["readOnly"] is True
    secret = volumes[mount["name"]]["secret"]
    assert secret["secretName"] == "camcore" and "optional" not in secret, "no key, no pod: never an open service"
    assert [item["path"] for item in secret["items"]] == [key_file.name]
    # group-readable by the pod's group only (0440; YAML reads the octal literal)
    assert secret["defaultMode"] == 0o440 and pod["securityContext"]["fsGroup"] == pod["securityContext"]["runAsGroup"]
    # the service reads that variable: a file at that name becomes the key
    assert "api_key_file" in Settings.model_fields


def test_pod_runs_as_the_image_user_on_a_read_only_root() -> None:
    pod = one("Deployment")["spec"]["template"]["spec"]
    c = container()
    (user,) = df.arguments("USER")
    uid, _, gid = user.partition(":")
    assert pod["securityContext"]["runAsNonRoot"] is True
    assert pod["securityContext"]["runAsUser"] == int(uid) and pod["securityContext"]["runAsGroup"] == int(gid)
    assert c["securityContext"]["readOnlyRootFilesystem"] is True
    assert c["securityContext"]["allowPrivilegeEscalation"] is False
    assert c["securityContext"]["capabilities"]["drop"] == ["ALL"]
    # the only place the service writes is matplotlib's cache: it must lie on a writable volume
    volumes = {v["name"]: v for v in pod["volumes"]}
    mounts = {m["mountPath"]: m["name"] for m in c["volumeMounts"]}
    mpl = df.env()["MPLCONFIGDIR"]
    mount = next(path for path in mounts if mpl.startswith(path.rstrip("/") + "/"))
    assert "emptyDir" in volumes[mounts[mount]]
    assert c["image"].endswith(f"camcore:{VERSION}"), "the image tag is the project's version"


def test_resources_fit_the_workers() -> None:
    c = container()
    workers = int(container_env()["CAMCORE_WORKERS"])
    requests, limits = c["resources"]["requests"], c["resources"]["limits"]
    # one core per worker (bench/README.md: workers_scaling, two workers on two cores ~1.7x one)
    assert cores(requests["cpu"]) == workers and cores(limits["cpu"]) >= workers
    assert mib(requests["memory"]) >= workers * WORKER_PLATEAU_MIB
    assert mib(limits["memory"]) >= workers * WORKER_WORST_MIB


@pytest.mark.anyio
async def test_probe_path_needs_no_api_key() -> None:
    # the Deployment sets a key (CAMCORE_API_KEY_FILE, its mounted Secret); the kubelet's probes carry no key
    from service.app import create_app
    from service.settings import Settings

    app = create_app(Settings(api_key="a-key-the-probe-does-not-send"))
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url="http://pod") as client:
        probe = await client.get(health_path())
        other = await client.get("/v1/curves")
    assert probe.status_code == 200 and probe.json()["status"] == "ok"
    assert other.status_code == 401, "the key is really required elsewhere, so the probe's 200 means something"


def check_jsonschema() -> str:
    path = shutil.which("check-jsonschema", path=str(Path(sys.executable).parent)) or shutil.which("check-jsonschema")
    assert path, "check-jsonschema is missing: it is pinned in requirements-dev.lock (make test installs it)"
    return path


def validate_compose(path: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([check_jsonschema(), "--builtin-schema", "vendor.compose-spec", str(path)],
                          capture_output=True, text=True, timeout=60, check=False)


def test_compose_file_is_valid(tmp_path: Path) -> None:
    proc = validate_compose(COMPOSE_FILE)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    # and the schema does reject: an unknown key and a port that is no port
    broken = yaml.safe_load(COMPOSE_FILE.read_text(encoding="utf-8"))
    broken["services"]["camcore"]["healthcheck"]["every"] = "30s"
    broken["services"]["camcore"]["ports"] = [{"target": "http"}]
    (tmp_path / "compose.yaml").write_text(yaml.safe_dump(broken), encoding="utf-8")
    assert validate_compose(tmp_path / "compose.yaml").returncode != 0


def test_compose_matches_the_image() -> None:
    compose = yaml.safe_load(COMPOSE_FILE.read_text(encoding="utf-8"))
    (service,) = compose["services"].values()
    assert (COMPOSE_FILE.parent / service["build"]["context"]).resolve() == ROOT
    assert service["image"] == f"camcore:{VERSION}"
    (exposed,) = df.exposed_ports()
    env = service["environment"]
    assert int(env["CAMCORE_PORT"]) == exposed
    (mapping,) = service["ports"]
    host, _, container_port = str(mapping).rpartition(":")
    assert int(container_port) == exposed and host
    # the same check as the image's HEALTHCHECK, the same user, a writable /tmp for matplotlib
    options, command = df.healthcheck()
    check = service["healthcheck"]
    assert check["test"] == ["CMD", *command]
    assert (check["interval"], check["timeout"], check["start_period"], str(check["retries"])) == (
        options["interval"], options["timeout"], options["start-period"], options["retries"])
    assert service["user"] == df.arguments("USER")[0]
    assert service["read_only"] is True and "/tmp" in service["tmpfs"]
    assert df.env()["MPLCONFIGDIR"].startswith("/tmp/")
    workers = int(env["CAMCORE_WORKERS"])
    limits = service["deploy"]["resources"]["limits"]
    assert float(limits["cpus"]) >= workers
    assert mib(limits["memory"]) >= workers * WORKER_WORST_MIB
