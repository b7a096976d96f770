"""Where obstacle records go: live console, JSON lines, annotated video, MCAP recording."""
