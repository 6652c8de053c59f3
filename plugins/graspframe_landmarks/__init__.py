"""The hand-landmark grasp classifier (needs the `hands` extra: MediaPipe Hands)."""
