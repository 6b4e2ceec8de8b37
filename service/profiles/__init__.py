"""The profiles domain of the service: specs, the bridge to camcore, routes."""
