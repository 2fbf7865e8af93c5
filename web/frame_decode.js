// Decodes a result fetched from GET /streams/ID/latest (docs/DAEMON.md). The body is
// [faces][labels][Draco chunks]: the faces (uint32 × 3 per triangle, POSITIONS results only,
// left out when the viewer already holds that X-Fq-Faces-Id) and the cluster labels (uint32
// per vertex, when clustered) as little-endian words, then the chunks as fqd published them
// (docs/PROTOCOL.md):
// - POSITIONS: Draco point clouds of consecutive vertex ranges, in order; the faces are the
//   input frame's (sent beside them).
// - MESH: Draco triangle meshes with a GENERIC uint32 "fq_vid" (global vertex id), merged
//   through it exactly like fq's C++ decode_frame.
// three's DRACOLoader is not used here: it picks attributes by type, and fq_vid is GENERIC;
// the metadata lookup it needs is in Draco's decoder module itself, which three ships.

function attributeData(M, decoder, geometry, attr, dataType, heap, components) {
  const n = geometry.num_points() * components;
  const bytes = n * 4;
  const ptr = M._malloc(bytes);
  decoder.GetAttributeDataArrayForAllPoints(geometry, attr, dataType, bytes, ptr);
  const out = new heap.constructor(heap.buffer, ptr, n).slice();
  M._free(ptr);
  return out;
}

function positionsOf(M, decoder, geometry) {
  const pos = decoder.GetAttribute(geometry, decoder.GetAttributeId(geometry, M.POSITION));
  return attributeData(M, decoder, geometry, pos, M.DT_FLOAT32, M.HEAPF32, 3);
}

// One POSITIONS chunk: its points' positions, in the frame's vertex order.
function decodePointCloud(M, decoder, bytes) {
  const cloud = new M.PointCloud();
  try {
    const status = decoder.DecodeArrayToPointCloud(bytes, bytes.byteLength, cloud);
    if (!status.ok() || cloud.ptr === 0) throw new Error('Draco: ' + status.error_msg());
    return positionsOf(M, decoder, cloud);
  } finally {
    M.destroy(cloud);
  }
}

// One MESH chunk: local positions and faces, and the global id of each local point.
function decodeMeshChunk(M, decoder, bytes) {
  const mesh = new M.Mesh();
  try {
    const status = decoder.DecodeArrayToMesh(bytes, bytes.byteLength, mesh);
    if (!status.ok() || mesh.ptr === 0) throw new Error('Draco: ' + status.error_msg());
    const vidId = decoder.GetAttributeIdByMetadataEntry(mesh, 'name', 'fq_vid');
    const faceBytes = mesh.num_faces() * 12;
    const fptr = M._malloc(faceBytes);
    decoder.GetTrianglesUInt32Array(mesh, faceBytes, fptr);
    const faces = new Uint32Array(M.HEAPU32.buffer, fptr, mesh.num_faces() * 3).slice();
    M._free(fptr);
    return {
      points: mesh.num_points(),
      faces,
      positions: positionsOf(M, decoder, mesh),
      vids: vidId < 0 ? null : attributeData(M, decoder, mesh, decoder.GetAttribute(mesh, vidId), M.DT_UINT32, M.HEAPU32, 1),
    };
  } finally {
    M.destroy(mesh);
  }
}

function mergeMeshChunks(chunks, vertexCount) {
  const n = vertexCount || chunks[0].points;  // a plain single Draco mesh: its own points
  const positions = new Float32Array(n * 3);
  const indices = new Uint32Array(chunks.reduce((s, c) => s + c.faces.length, 0));
  let f = 0;
  for (const c of chunks) {
    for (let p = 0; p < c.points; ++p) {
      const g = c.vids ? c.vids[p] : p;
      positions[3 * g] = c.positions[3 * p];
      positions[3 * g + 1] = c.positions[3 * p + 1];
      positions[3 * g + 2] = c.positions[3 * p + 2];
    }
    for (let k = 0; k < c.faces.length; ++k) indices[f++] = c.vids ? c.vids[c.faces[k]] : c.faces[k];
  }
  return { positions, indices };
}

function concatPositions(parts, vertexCount) {
  const positions = new Float32Array(parts.reduce((s, p) => s + p.length, 0));
  let at = 0;
  for (const p of parts) {
    positions.set(p, at);
    at += p.length;
  }
  if (positions.length !== vertexCount * 3)
    throw new Error(`chunks carry ${positions.length / 3} points, the frame has ${vertexCount} vertices`);
  return positions;
}

// buffer: the response body; meta: {form ('positions' | 'mesh'), facesBytes, labelsBytes,
// sizes (chunk byte sizes), vertexCount}; faces: the Uint32Array the viewer holds for this
// result's faces id when the body leaves them out. Returns {positions, indices, labels or null}.
export function decodeFrame(M, buffer, meta, faces) {
  const labels = meta.labelsBytes ? new Uint32Array(buffer, meta.facesBytes, meta.labelsBytes / 4) : null;
  const decoder = new M.Decoder();
  try {
    const chunks = [];
    let at = meta.facesBytes + meta.labelsBytes;
    for (const size of meta.sizes) {
      const bytes = new Int8Array(buffer, at, size);
      chunks.push(meta.form === 'mesh' ? decodeMeshChunk(M, decoder, bytes) : decodePointCloud(M, decoder, bytes));
      at += size;
    }
    if (meta.form === 'mesh') return { ...mergeMeshChunks(chunks, meta.vertexCount), labels };
    const indices = meta.facesBytes ? new Uint32Array(buffer, 0, meta.facesBytes / 4) : faces;
    if (!indices) throw new Error('a POSITIONS result without its faces');
    return { positions: concatPositions(chunks, meta.vertexCount), indices, labels };
  } finally {
    M.destroy(decoder);
  }
}

// The colour of a cluster label, as fq's PLY writer gives it (io/cluster_colors.cpp):
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
