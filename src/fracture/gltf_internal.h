// Internal: what the glTF writer and reader share (see docs/gltf.md).
#pragma once

/// Version of the asset.extras.breakables schema.
#define BK_GLTF_EXTRAS_VERSION 1

/// GLB container: "glTF", version 2, then chunks of (length, type, data).
#define BK_GLB_MAGIC 0x46546C67u
#define BK_GLB_VERSION 2u
#define BK_GLB_CHUNK_JSON 0x4E4F534Au
#define BK_GLB_CHUNK_BIN 0x004E4942u

/// The prefix of a .gltf buffer's data URI.
#define BK_GLTF_DATA_URI "data:application/octet-stream;base64,"
