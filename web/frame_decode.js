// Decodes a result fetched from GET /streams/ID/latest: the Draco chunks one after the
// other, each a triangle mesh with POSITION, a GENERIC uint32 "fq_vid" (global vertex id) and,
// when clustered, a GENERIC uint32 "fq_label" (docs/PROTOCOL.md). Chunks are merged through
// fq_vid exactly like fq's C++ decode_frame. three's DRACOLoader is not used here: it picks
// attributes by type, and both fq_vid and fq_label are GENERIC; the metadata lookup they need
// is in Draco's decoder module itself, which three ships beside DRACOLoader.

function attributeData(M, decoder, mesh, attr, dataType, heap, components) {
  const n = mesh.num_points() * components;
  const bytes = n * 4;
  const ptr = M._malloc(bytes);
  decoder.GetAttributeDataArrayForAllPoints(mesh, attr, dataType, bytes, ptr);
  const out = new heap.constructor(heap.buffer, ptr, n).slice();
  M._free(ptr);
  return out;
}

function metadataAttribute(decoder, mesh, name) {
  const id = decoder.GetAttributeIdByMetadataEntry(mesh, 'name', name);
  return id < 0 ? null : decoder.GetAttribute(mesh, id);
}

function decodeChunk(M, decoder, bytes) {
  const mesh = new M.Mesh();
  try {
    const status = decoder.DecodeArrayToMesh(bytes, bytes.byteLength, mesh);
    if (!status.ok() || mesh.ptr === 0) throw new Error('Draco: ' + status.error_msg());
    const pos = decoder.GetAttribute(mesh, decoder.GetAttributeId(mesh, M.POSITION));
    const vid = metadataAttribute(decoder, mesh, 'fq_vid');
    const label = metadataAttribute(decoder, mesh, 'fq_label');
    const faceBytes = mesh.num_faces() * 12;
    const fptr = M._malloc(faceBytes);
    decoder.GetTrianglesUInt32Array(mesh, faceBytes, fptr);
    const faces = new Uint32Array(M.HEAPU32.buffer, fptr, mesh.num_faces() * 3).slice();
    M._free(fptr);
    return {
      points: mesh.num_points(),
      faces,
      positions: attributeData(M, decoder, mesh, pos, M.DT_FLOAT32, M.HEAPF32, 3),
      vids: vid ? attributeData(M, decoder, mesh, vid, M.DT_UINT32, M.HEAPU32, 1) : null,
      labels: label ? attributeData(M, decoder, mesh, label, M.DT_UINT32, M.HEAPU32, 1) : null,
    };
  } finally {
    M.destroy(mesh);
  }
}

// buffer: ArrayBuffer of the concatenated chunks; sizes: their byte sizes; vertexCount: the
// frame's vertex count (X-Fq-Vertex-Count). Returns {positions, indices, labels or null}.
export function decodeFrame(M, buffer, sizes, vertexCount) {
  const decoder = new M.Decoder();
  try {
    const chunks = [];
    let at = 0;
    for (const size of sizes) {
      chunks.push(decodeChunk(M, decoder, new Int8Array(buffer, at, size)));
      at += size;
    }
    const n = vertexCount || chunks[0].points;  // a plain single Draco mesh: its own points
    const positions = new Float32Array(n * 3);
    const labels = chunks.every((c) => c.labels) ? new Uint32Array(n) : null;
    const indices = new Uint32Array(chunks.reduce((s, c) => s + c.faces.length, 0));
    let f = 0;
    for (const c of chunks) {
      for (let p = 0; p < c.points; ++p) {
        const g = c.vids ? c.vids[p] : p;
        positions[3 * g] = c.positions[3 * p];
        positions[3 * g + 1] = c.positions[3 * p + 1];
        positions[3 * g + 2] = c.positions[3 * p + 2];
        if (labels) labels[g] = c.labels[p];
      }
      for (let k = 0; k < c.faces.length; ++k) indices[f++] = c.vids ? c.vids[c.faces[k]] : c.faces[k];
    }
    return { positions, indices, labels };
  } finally {
    M.destroy(decoder);
  }
}

// The colour of a cluster label, as fq's PLY writer gives it (proto/cluster_colors.cpp):
// golden-ratio hues with three saturation/value levels, so a viewer and a saved PLY agree.
export function clusterColor(label, out, offset) {
  const x = label * 0.6180339887498949;
  const h = x - Math.floor(x);
  const s = [0.75, 0.55, 0.95][label % 3];
  const v = [0.95, 0.8, 0.65][label % 3];
  const h6 = h * 6;
  const sector = Math.floor(h6) % 6;
  const fr = h6 - Math.floor(h6);
  const p = v * (1 - s), q = v * (1 - s * fr), t = v * (1 - s * (1 - fr));
  const rgb = [[v, t, p], [q, v, p], [p, v, t], [p, q, v], [t, p, v], [v, p, q]][sector];
  out[offset] = rgb[0];
  out[offset + 1] = rgb[1];
  out[offset + 2] = rgb[2];
}
