"""The serial link to the board: ``connection`` (reader thread, handshake, commands, reconnect)
and ``ports`` (finding the board's port by USB VID:PID). Receives bytes, gives decoded
messages stamped with the host-monotonic time of their arrival.
"""
