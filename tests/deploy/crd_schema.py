# SPDX-License-Identifier: Apache-2.0
"""Validation of a manifest against a CRD's structural OpenAPI v3 schema, offline, as the API
server does it for custom resources (the subset of keywords CRD schemas use): type, properties,
required, additionalProperties, items, enum, pattern, minimum, maximum, minLength, minItems,
anyOf, x-kubernetes-int-or-string and x-kubernetes-preserve-unknown-fields. A field the schema does
not know is an error, as with `kubectl apply` under strict field validation (a typo such as
`trigers` would otherwise be dropped in silence). CEL rules (x-kubernetes-validations) are not
evaluated: callers check what those rules say themselves.

Written here rather than taken from python3-jsonschema: OpenAPI's int-or-string and
preserve-unknown-fields are not JSON Schema, and the check needs nothing beyond Python and PyYAML.
"""
import re

import yaml

_TYPES = {
    "object": lambda v: isinstance(v, dict),
    "array": lambda v: isinstance(v, list),
    "string": lambda v: isinstance(v, str),
    "integer": lambda v: isinstance(v, int) and not isinstance(v, bool),
    "number": lambda v: isinstance(v, (int, float)) and not isinstance(v, bool),
    "boolean": lambda v: isinstance(v, bool),
}


def load_crd_schema(path):
    """(apiVersion, kind, openAPIV3Schema) of a schema file of tests/deploy/schemas."""
    with open(path) as f:
        crd = yaml.safe_load(f)
    return f"{crd['group']}/{crd['version']}", crd["kind"], crd["openAPIV3Schema"]


def type_mismatch(value, schema, path):
    """The error of `value` against the schema's `type`, or None; a type no validator knows
    raises, so that a schema is never half checked."""
    if schema["type"] not in _TYPES:
        raise ValueError(f"schema at {path}: unknown type {schema['type']}")
    return None if _TYPES[schema["type"]](value) else \
        f"{path}: {value!r} is not of type {schema['type']}"


def enum_errors(value, schema, path):
    if "enum" in schema and value not in schema["enum"]:
        return [f"{path}: {value!r} is not one of {schema['enum']}"]
    return []


def validate(value, schema, path="$"):
    """The list of errors of `value` against `schema`, each naming the offending field by path
    (e.g. `$.spec.triggers[0].type: missing`); empty when it validates."""
    errors = []
    if "anyOf" in schema:
        if not any(not validate(value, option, path) for option in schema["anyOf"]):
            errors.append(f"{path}: {value!r} matches none of {schema['anyOf']}")
    if schema.get("x-kubernetes-int-or-string"):
        if not (_TYPES["integer"](value) or isinstance(value, str)):
            errors.append(f"{path}: {value!r} is neither an integer nor a string")
    elif "type" in schema and (mismatch := type_mismatch(value, schema, path)):
        return errors + [mismatch]
    errors += enum_errors(value, schema, path)
    if isinstance(value, str):
        if "pattern" in schema and not re.search(schema["pattern"], value):
            errors.append(f"{path}: {value!r} does not match {schema['pattern']}")
        if len(value) < schema.get("minLength", 0):
            errors.append(f"{path}: shorter than {schema['minLength']} characters")
    if _TYPES["number"](value):
        if "minimum" in schema and value < schema["minimum"]:
            errors.append(f"{path}: {value} is below the minimum {schema['minimum']}")
        if "maximum" in schema and value > schema["maximum"]:
            errors.append(f"{path}: {value} is above the maximum {schema['maximum']}")
    if isinstance(value, list):
        if len(value) < schema.get("minItems", 0):
            errors.append(f"{path}: fewer than {schema['minItems']} items")
        for i, item in enumerate(value):
            errors += validate(item, schema.get("items", {}), f"{path}[{i}]")
    if isinstance(value, dict):
        for name in schema.get("required", []):
            if name not in value:
                errors.append(f"{path}.{name}: missing")
        properties = schema.get("properties", {})
        extra = schema.get("additionalProperties")
        for name, item in value.items():
            if name in properties:
                errors += validate(item, properties[name], f"{path}.{name}")
            elif isinstance(extra, dict):
                errors += validate(item, extra, f"{path}.{name}")
            elif extra is True or schema.get("x-kubernetes-preserve-unknown-fields"):
                continue
            elif properties or extra is False:
                errors.append(f"{path}.{name}: unknown field")
    return errors
