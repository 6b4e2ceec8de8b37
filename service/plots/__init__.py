"""The plots domain of the service: specs, the bridge to camcore, routes."""
