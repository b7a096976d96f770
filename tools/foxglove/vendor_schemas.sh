#!/usr/bin/env bash
# Re-vendor the published Foxglove JSON schemas that obstacle-fusion writes.
# Source: the @foxglove/schemas npm package (MIT, Foxglove); needs npm and node.
# Usage: bash tools/foxglove/vendor_schemas.sh [VERSION]   (default: the version below)
set -euo pipefail
version="${1:-2.1.0}"
here="$(cd "$(dirname "$0")/../.." && pwd)"
dest="$here/host/obstacle_fusion/outputs/foxglove_jsonschema"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
(cd "$work" && npm pack -q "@foxglove/schemas@$version" >/dev/null && tar xzf ./*.tgz)
node -e '
const fs = require("fs");
const s = require(process.argv[1] + "/package/dist/jsonschema/index.js");
const names = ["CompressedImage", "ImageAnnotations", "SceneUpdate", "FrameTransform",
               "Log", "CameraCalibration"];
for (const n of names) {
  fs.writeFileSync(`${process.argv[2]}/foxglove.${n}.json`, JSON.stringify(s[n]) + "\n");
}
' "$work" "$dest"
echo "@foxglove/schemas $version" > "$dest/VERSION"
echo "vendored $(ls "$dest"/*.json | wc -l) schemas of @foxglove/schemas $version into $dest"
