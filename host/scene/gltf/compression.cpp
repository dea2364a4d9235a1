// The glTF loader's compressed geometry: EXT_meshopt_compression bufferViews (meshoptimizer's
// decoders) and KHR_draco_mesh_compression primitives (Draco's decoder), each decoded into the
// bytes an uncompressed file would hold, so that accessors.cpp reads both the same way. Every
// decoded size comes from the JSON and is checked against the limits before it is allocated;
// a decoder that fails, or decodes to other counts than the JSON says, is bad input.
#include <draco/compression/decode.h>
#include <meshoptimizer.h>

#include <cmath>
#include <cstring>

#include "scene/gltf/gltf_internal.h"

namespace clpt::gltf {

bool adapt_compressed_for_tinygltf(nlohmann::json& doc) {
  bool changed = false;
  auto buffers = doc.find("buffers");
  if (buffers != doc.end() && buffers->is_array()) {
    for (auto& b : *buffers) {
      if (!b.is_object() || b.contains("uri")) continue;
      auto ext = b.find("extensions");
      if (ext == b.end() || !ext->is_object()) continue;
      auto meshopt = ext->find("EXT_meshopt_compression");
      if (meshopt == ext->end() || !meshopt->is_object()) continue;
      auto fallback = meshopt->find("fallback");
      if (fallback == meshopt->end() || !fallback->is_boolean() || !fallback->get<bool>()) continue;
      b["uri"] = "data:application/octet-stream;base64,AA==";
      b["byteLength"] = 1;
      changed = true;
    }
  }
  auto meshes = doc.find("meshes");
  if (meshes != doc.end() && meshes->is_array()) {
    for (auto& mesh : *meshes) {
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
      for (auto& p : mesh["primitives"]) {
        if (!p.is_object() || !p.contains("indices")) continue;
        auto ext = p.find("extensions");
        if (ext == p.end() || !ext->is_object()) continue;
        auto draco = ext->find("KHR_draco_mesh_compression");
        if (draco == ext->end() || !draco->is_object()) continue;
        (*draco)[kDracoIndicesKey] = p["indices"];
        p.erase("indices");
        changed = true;
      }
    }
  }
  return changed;
}

int Converter::indices_accessor(const tinygltf::Primitive& p) const {
  auto draco = p.extensions.find("KHR_draco_mesh_compression");
  if (draco == p.extensions.end() || !draco->second.IsObject() || !draco->second.Has(kDracoIndicesKey))
    return p.indices;
  const tinygltf::Value& v = draco->second.Get(kDracoIndicesKey);
  return v.IsInt() ? v.GetNumberAsInt() : -1;  // check_indices has checked the glTFid
}

void Converter::reserve_decoded(uint64_t bytes, const std::string& what) const {
  std::string which;
  const uint64_t budget = limits_.memory_budget(file_bytes_, &which);
  if (bytes > budget || decoded_bytes_ > budget - bytes)
    fail(what + " decodes to " + bytes_text(bytes) + ", which with the " + bytes_text(decoded_bytes_) +
         " decoded before is more than the budget of " + bytes_text(budget) + " (" + which + ")");
  decoded_bytes_ += bytes;
}

namespace {

// A non-negative integer member of an extension object; `def` < 0: required.
uint64_t integer_member(const tinygltf::Value& obj, const char* key, int64_t def, const std::string& where,
                        const Fail& fail) {
  if (!obj.Has(key)) {
    if (def < 0) fail(where + " has no " + key);
    return uint64_t(def);
  }
  const tinygltf::Value& v = obj.Get(key);
  const double d = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
  if (!(d >= 0.0 && d <= 9007199254740992.0 && std::floor(d) == d))
    fail(where + " " + key + " is not a non-negative integer");
  return uint64_t(d);
}

std::string string_member(const tinygltf::Value& obj, const char* key, const char* def, const std::string& where,
                          const Fail& fail) {
  if (!obj.Has(key)) {
    if (!def) fail(where + " has no " + key);
    return def;
  }
  const tinygltf::Value& v = obj.Get(key);
  if (!v.IsString()) fail(where + " " + key + " is not a string");
  return v.Get<std::string>();
}

}  // namespace

// One EXT_meshopt_compression bufferView, decoded (count x byteStride bytes) on first use. The
// checks before each decoder call are its preconditions, which meshoptimizer asserts.
const std::vector<unsigned char>& Converter::meshopt_view(int index, const tinygltf::Value& ext) const {
  auto known = meshopt_views_.find(index);
  if (known != meshopt_views_.end()) return known->second;
  const std::string where = "bufferView " + std::to_string(index) + " EXT_meshopt_compression";
  const Fail f = [this](const std::string& m) { fail(m); };
  if (!ext.IsObject()) fail(where + " is not an object");
  const uint64_t buffer = integer_member(ext, "buffer", -1, where, f);
  const uint64_t offset = integer_member(ext, "byteOffset", 0, where, f);
  const uint64_t length = integer_member(ext, "byteLength", -1, where, f);
  const uint64_t stride = integer_member(ext, "byteStride", -1, where, f);
  const uint64_t count = integer_member(ext, "count", -1, where, f);
  const std::string mode = string_member(ext, "mode", nullptr, where, f);
  const std::string filter = string_member(ext, "filter", "NONE", where, f);

  if (buffer >= m_.buffers.size())
    fail(where + " refers to buffer " + std::to_string(buffer) + ", which does not exist (the file has " +
         std::to_string(m_.buffers.size()) + ")");
  const std::vector<unsigned char>& src = m_.buffers[size_t(buffer)].data;
  if (u128(offset) + u128(length) > u128(src.size()))
    fail(where + " reads bytes " + std::to_string(offset) + ".." + to_string_u128(u128(offset) + length) +
         " past the end of buffer " + std::to_string(buffer) + " (" + std::to_string(src.size()) + " bytes)");
  if (mode == "ATTRIBUTES") {
    if (stride == 0 || stride > 256 || stride % 4 != 0)
      fail(where + " has byteStride " + std::to_string(stride) + "; ATTRIBUTES needs a multiple of 4 up to 256");
  } else if (mode == "TRIANGLES" || mode == "INDICES") {
    if (stride != 2 && stride != 4)
      fail(where + " has byteStride " + std::to_string(stride) + "; " + mode + " needs 2 or 4");
    if (mode == "TRIANGLES" && count % 3 != 0)
      fail(where + " has count " + std::to_string(count) + ", which is not a multiple of 3 (TRIANGLES)");
  } else {
    fail(where + " has mode " + printable(mode) + "; expected ATTRIBUTES, TRIANGLES or INDICES");
  }
  if (filter != "NONE") {
    if (mode != "ATTRIBUTES") fail(where + " has filter " + printable(filter) + " on " + mode + " data");
    const bool ok = filter == "OCTAHEDRAL"    ? stride == 4 || stride == 8
                    : filter == "QUATERNION"  ? stride == 8
                    : filter == "EXPONENTIAL" ? stride % 4 == 0
                                              : false;
    if (!ok)
      fail(where + " has filter " + printable(filter) + " with byteStride " + std::to_string(stride) +
           " (OCTAHEDRAL: 4 or 8, QUATERNION: 8, EXPONENTIAL: a multiple of 4)");
  }
  if (count > limits_.accessor_count)
    fail(where + " has count " + std::to_string(count) + ", more than the limit of " +
         std::to_string(limits_.accessor_count) + " (--limit accessor-count=N)");
  const uint64_t bytes = count * stride;  // both bounded above: no overflow
  reserve_decoded(bytes, where);

  std::vector<unsigned char> out(static_cast<size_t>(bytes));
  const unsigned char* data = src.data() + offset;
  int rc;
  if (mode == "ATTRIBUTES")
    rc = meshopt_decodeVertexBuffer(out.data(), size_t(count), size_t(stride), data, size_t(length));
  else if (mode == "TRIANGLES")
    rc = meshopt_decodeIndexBuffer(out.data(), size_t(count), size_t(stride), data, size_t(length));
  else
    rc = meshopt_decodeIndexSequence(out.data(), size_t(count), size_t(stride), data, size_t(length));
  if (rc != 0)
    fail(where + ": meshoptimizer cannot decode its " + std::to_string(length) + " bytes into " +
         std::to_string(count) + " elements of " + std::to_string(stride) + " bytes (error " + std::to_string(rc) +
         "): the data is damaged or the counts are wrong");
  if (filter == "OCTAHEDRAL") meshopt_decodeFilterOct(out.data(), size_t(count), size_t(stride));
  else if (filter == "QUATERNION") meshopt_decodeFilterQuat(out.data(), size_t(count), size_t(stride));
  else if (filter == "EXPONENTIAL") meshopt_decodeFilterExp(out.data(), size_t(count), size_t(stride));
  return meshopt_views_.emplace(index, std::move(out)).first->second;
}

namespace {

// Draco attribute values as the accessor's component type, tightly packed.
template <class T>
bool put_values(const draco::PointAttribute& a, const draco::Mesh& mesh, int ncomp, std::vector<unsigned char>* out) {
  const size_t n = mesh.num_points();
  out->resize(n * size_t(ncomp) * sizeof(T));
  T value[4];
  for (size_t i = 0; i < n; ++i) {
    if (!a.ConvertValue<T>(a.mapped_index(draco::PointIndex(uint32_t(i))), int8_t(ncomp), value)) return false;
    std::memcpy(out->data() + i * size_t(ncomp) * sizeof(T), value, size_t(ncomp) * sizeof(T));
  }
  return true;
}

}  // namespace

// A KHR_draco_mesh_compression primitive: its bufferView decoded by Draco, each attribute the
// extension names (and the indices) stored as the bytes its accessor describes.
void Converter::decode_draco(const tinygltf::Primitive& p, const tinygltf::Value& ext, const std::string& where) {
  const std::string desc = where + " KHR_draco_mesh_compression";
  const Fail f = [this](const std::string& m) { fail(m); };
  if (!ext.IsObject()) fail(desc + " is not an object");
  const uint64_t view_index = integer_member(ext, "bufferView", -1, desc, f);
  if (view_index >= m_.bufferViews.size())
    fail(desc + " refers to bufferView " + std::to_string(view_index) + ", which does not exist (the file has " +
         std::to_string(m_.bufferViews.size()) + ")");
  if (!ext.Has("attributes") || !ext.Get("attributes").IsObject()) fail(desc + " has no attributes object");
  const tinygltf::Value& attributes = ext.Get("attributes");

  // Every decoded size is known from the accessors before Draco runs: check them first.
  uint64_t expected_bytes = 0;
  auto accessor_of = [&](const std::string& name) -> int {
    auto it = p.attributes.find(name);
    if (it == p.attributes.end())
      fail(desc + " codes attribute " + printable(name) + ", which the primitive does not have");
    if (it->second < 0 || size_t(it->second) >= m_.accessors.size())
      fail(name + " of " + where + " refers to accessor " + std::to_string(it->second) +
           ", which does not exist (the file has " + std::to_string(m_.accessors.size()) + ")");
    return it->second;
  };
  for (const std::string& name : attributes.Keys()) {
    const tinygltf::Accessor& acc = m_.accessors[size_t(accessor_of(name))];
    if (acc.count > limits_.accessor_count)
      fail(accessor_desc(accessor_of(name), name + " of " + where) + " has count " + std::to_string(acc.count) +
           ", more than the limit of " + std::to_string(limits_.accessor_count) + " (--limit accessor-count=N)");
    expected_bytes += acc.count * 16;  // at most 4 components of 4 bytes
  }
  const int indices = indices_accessor(p);
  if (indices < 0 || size_t(indices) >= m_.accessors.size())
    fail(desc + ": the primitive has no indices accessor, which Draco primitives need");
  const tinygltf::Accessor& idx_acc = m_.accessors[size_t(indices)];
  if (idx_acc.count > limits_.accessor_count)
    fail(accessor_desc(indices, "indices of " + where) + " has count " + std::to_string(idx_acc.count) +
         ", more than the limit of " + std::to_string(limits_.accessor_count) + " (--limit accessor-count=N)");
  expected_bytes += idx_acc.count * 4;
  // Draco's own mesh holds about the same again (positions as floats, corner tables).
  reserve_decoded(2 * expected_bytes, desc);

  const ViewBytes view = buffer_view(int(view_index), desc);
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(view.data), size_t(view.length));
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok())
    fail(desc + ": Draco cannot decode bufferView " + std::to_string(view_index) + " (" +
         std::to_string(view.length) + " bytes): " + one_line(decoded.status().error_msg_string()));
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  if (!mesh) fail(desc + ": Draco decoded no mesh");
  const uint64_t points = mesh->num_points(), faces = mesh->num_faces();

  for (const std::string& name : attributes.Keys()) {
    const int ai = accessor_of(name);
    const tinygltf::Accessor& acc = m_.accessors[size_t(ai)];
    const std::string adesc = accessor_desc(ai, name + " of " + where);
    const tinygltf::Value& id = attributes.Get(name);
    if (!id.IsInt() || id.GetNumberAsInt() < 0) fail(desc + " attribute " + name + " is not a Draco attribute id");
    const draco::PointAttribute* a = mesh->GetAttributeByUniqueId(uint32_t(id.GetNumberAsInt()));
    if (!a) fail(desc + " attribute " + name + " names Draco attribute " + std::to_string(id.GetNumberAsInt()) +
                 ", which the Draco data does not have");
    if (acc.count != points)
      fail(adesc + " has count " + std::to_string(acc.count) + ", but the Draco data has " +
           std::to_string(points) + " points");
    const int ncomp = type_components(acc.type);
    if (ncomp < 1 || ncomp > 4 || a->num_components() < ncomp)
      fail(adesc + " has " + std::to_string(ncomp) + " components, but Draco attribute " +
           std::to_string(id.GetNumberAsInt()) + " has " + std::to_string(int(a->num_components())));
    std::vector<unsigned char> bytes;
    bool ok = false;
    switch (acc.componentType) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: ok = put_values<float>(*a, *mesh, ncomp, &bytes); break;
      case TINYGLTF_COMPONENT_TYPE_BYTE: ok = put_values<int8_t>(*a, *mesh, ncomp, &bytes); break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: ok = put_values<uint8_t>(*a, *mesh, ncomp, &bytes); break;
      case TINYGLTF_COMPONENT_TYPE_SHORT: ok = put_values<int16_t>(*a, *mesh, ncomp, &bytes); break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: ok = put_values<uint16_t>(*a, *mesh, ncomp, &bytes); break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: ok = put_values<uint32_t>(*a, *mesh, ncomp, &bytes); break;
      default: break;
    }
    if (!ok)
      fail(adesc + ": the Draco values do not convert to its component type " +
           std::to_string(acc.componentType));
    draco_accessors_[ai] = std::move(bytes);
  }

  if (idx_acc.count != faces * 3)
    fail(accessor_desc(indices, "indices of " + where) + " has count " + std::to_string(idx_acc.count) +
         ", but the Draco data has " + std::to_string(faces) + " triangles (" + std::to_string(faces * 3) +
         " indices)");
  const int ict = idx_acc.componentType;
  const size_t isize = ict == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                       : ict == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                       : ict == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                       : 0;
  if (isize == 0) return;  // read_indices names the bad component type
  const uint64_t max_index = isize == 4 ? 0xFFFFFFFFull : (uint64_t(1) << (8 * isize)) - 1;
  std::vector<unsigned char> bytes(size_t(faces * 3) * isize);
  for (uint64_t t = 0; t < faces; ++t) {
    const draco::Mesh::Face& face = mesh->face(draco::FaceIndex(uint32_t(t)));
    for (int k = 0; k < 3; ++k) {
      const uint64_t v = face[k].value();
      if (v > max_index)
        fail(desc + ": Draco index " + std::to_string(v) + " does not fit the indices accessor's " +
             std::to_string(isize * 8) + "-bit components");
      const uint32_t v32 = uint32_t(v);
      std::memcpy(bytes.data() + (size_t(t) * 3 + size_t(k)) * isize, &v32, isize);  // little-endian
    }
  }
  draco_accessors_[indices] = std::move(bytes);
}

}  // namespace clpt::gltf
