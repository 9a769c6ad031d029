# SPDX-License-Identifier: Apache-2.0
"""Validation of a manifest of a core Kubernetes kind (Deployment, Service, ...) against Kubernetes'
own OpenAPI v3 schema, offline: schemas/kubernetes-core.json, the definitions the kinds reach,
extracted from api/openapi-spec/v3 by schemas/extract_core_schemas.py.

What the API server checks with `kubectl apply --validate=strict`, as far as the schema says it:
a field the schema does not know is an error (a typo such as `imagePullPolicyy` would otherwise be
dropped), required fields are there, every value has its type (int32 and int64 in range, `byte`
base64), int-or-string and quantities are an integer or a string (a number), and lists the schema
keys as maps or sets (x-kubernetes-list-type) hold no duplicate. The keywords are those the
documents use: $ref to #/components/schemas/, allOf, oneOf, type, format, properties,
additionalProperties, items, required, enum (none in today's documents: Kubernetes states its
enums in descriptions), the x-kubernetes-list-* annotations; a keyword this module does not know
fails loudly, so that a schema refreshed from a newer Kubernetes cannot be half checked. A null
value is accepted, as the API server decodes it to the field's zero value. The API server's own
validation beyond the schema (names, label syntax, port ranges, ...) is not repeated here.
"""
import base64
import binascii
import json

from crd_schema import _TYPES, enum_errors, type_mismatch

REF = "#/components/schemas/"
# Keywords that do not constrain a value (extract_core_schemas.py drops most of them).
_ANNOTATIONS = {"description", "default", "example", "x-kubernetes-patch-strategy",
                "x-kubernetes-patch-merge-key", "x-kubernetes-map-type", "x-kubernetes-unions",
                "x-kubernetes-group-version-kind"}
_KEYWORDS = {"$ref", "allOf", "oneOf", "type", "format", "properties", "additionalProperties",
             "items", "required", "enum", "x-kubernetes-list-type", "x-kubernetes-list-map-keys"}
_RANGES = {"int32": (-2**31, 2**31 - 1), "int64": (-2**63, 2**63 - 1)}


def load(path):
    """{version: CoreSchemas} of a file written by extract_core_schemas.py."""
    with open(path) as f:
        document = json.load(f)
    return {version: CoreSchemas(version, extracted["kinds"], extracted["schemas"])
            for version, extracted in document["versions"].items()}


class CoreSchemas:
    """The schemas of one Kubernetes version."""

    def __init__(self, version, kinds, schemas):
        self.version = version
        self.kinds = {tuple(key.split(" ")): name for key, name in kinds.items()}
        self.schemas = schemas

    def knows(self, api_version, kind):
        return (api_version, kind) in self.kinds

    def validate_document(self, doc):
        """The errors of a manifest (its apiVersion and kind must be known: knows())."""
        name = self.kinds[(doc.get("apiVersion"), doc.get("kind"))]
        return self.validate(doc, {"$ref": REF + name})

    def validate(self, value, schema, path="$"):
        """The list of errors of `value` against `schema`, each naming the offending field by
        path (e.g. `$.spec.template.spec.containers[0].name: missing`); empty when it
        validates."""
        unknown = set(schema) - _KEYWORDS - _ANNOTATIONS
        if unknown:
            raise ValueError(f"schema at {path}: keywords {sorted(unknown)} are not understood")
        if value is None:
            return []
        errors = []
        if "$ref" in schema:
            reference = schema["$ref"]
            if not reference.startswith(REF) or reference[len(REF):] not in self.schemas:
                raise ValueError(f"schema at {path}: cannot resolve {reference}")
            errors += self.validate(value, self.schemas[reference[len(REF):]], path)
        for part in schema.get("allOf", []):
            errors += self.validate(value, part, path)
        if "oneOf" in schema:
            matching = [o for o in schema["oneOf"] if not self.validate(value, o, path)]
            if len(matching) != 1:
                choices = " or ".join(o.get("type", json.dumps(o)) for o in schema["oneOf"])
                errors.append(f"{path}: {value!r} is not exactly one of {choices}"
                              + (f" ({schema['format']})" if "format" in schema else ""))
        if "type" in schema and (mismatch := type_mismatch(value, schema, path)):
            return errors + [mismatch]
        errors += enum_errors(value, schema, path)
        errors += self._format(value, schema.get("format"), path)
        if isinstance(value, list):
            for i, item in enumerate(value):
                errors += self.validate(item, schema.get("items", {}), f"{path}[{i}]")
            errors += _duplicates(value, schema, path)
        if isinstance(value, dict):
            errors += self._object(value, schema, path)
        return errors

    def _format(self, value, format_, path):
        if format_ in _RANGES and _TYPES["integer"](value):
            low, high = _RANGES[format_]
            if not low <= value <= high:
                return [f"{path}: {value} is out of the range of {format_}"]
        if format_ == "byte" and isinstance(value, str):
            try:
                base64.b64decode(value, validate=True)
            except binascii.Error:
                return [f"{path}: {value!r} is not base64 (format byte)"]
        return []  # int-or-string (with its oneOf), date-time and the like: not checked further

    def _object(self, value, schema, path):
        errors = []
        for name in schema.get("required", []):
            if value.get(name) is None:
                errors.append(f"{path}.{name}: missing (required)")
        properties = schema.get("properties", {})
        extra = schema.get("additionalProperties")
        for name, item in value.items():
            if name in properties:
                errors += self.validate(item, properties[name], f"{path}.{name}")
            elif isinstance(extra, dict):
                errors += self.validate(item, extra, f"{path}.{name}")
            elif extra is True:
                continue
            elif properties or extra is False:
                errors.append(f"{path}.{name}: unknown field")
            # An object schema with neither (FieldsV1, RawExtension) takes any fields.
        return errors


def _duplicates(items, schema, path):
    """A list-type map must not repeat a key, a set not a value (as the API server rejects)."""
    list_type = schema.get("x-kubernetes-list-type")
    if list_type == "map":
        keys = schema.get("x-kubernetes-list-map-keys", [])
        identity = [tuple(json.dumps(i.get(k)) for k in keys) if isinstance(i, dict) else None
                    for i in items]
        what = f"key ({', '.join(keys)})"
    elif list_type == "set":
        identity = [json.dumps(i, sort_keys=True) for i in items]
        what = "value"
    else:
        return []
    errors = []
    for i, key in enumerate(identity):
        if key is not None and key in identity[:i]:
            errors.append(f"{path}[{i}]: duplicate {what} of {path}[{identity.index(key)}] "
                          f"(x-kubernetes-list-type {list_type})")
    return errors
