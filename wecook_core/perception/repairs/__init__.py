"""Repairs of what real observations miss: detector jitter, hands lost while they keep still, objects hidden by the
hand carrying them, holds by unseen hands."""
