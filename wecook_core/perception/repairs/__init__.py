"""Repairs of what real observations miss: objects hidden by the hand carrying them, holds by unseen hands."""
