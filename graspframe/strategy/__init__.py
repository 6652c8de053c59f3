"""The grasp strategy of METHOD.md sections 3 and 4: plan, execute, human references."""
