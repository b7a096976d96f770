"""Messages as JSON-ready dicts: field values with enum fields given by name."""

from __future__ import annotations

import dataclasses
from typing import Any

from obstacle_fusion.protocol.generated import ENUM_OF_FIELD, Message


def message_to_dict(msg: Message) -> dict[str, Any]:
    out: dict[str, Any] = {"msg": msg.NAME}
    for field in dataclasses.fields(msg):
        value = getattr(msg, field.name)
        enum = ENUM_OF_FIELD.get((msg.NAME, field.name))
        if enum is not None:
            try:
                value = enum(value).name.lower()
            except ValueError:
                value = f"unknown({value})"
        out[field.name] = value
    return out
