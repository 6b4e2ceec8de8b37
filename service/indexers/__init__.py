"""The indexers domain of the service: specs, the bridge to camcore, routes."""
