// The glTF loader's accessors: buffer views and accessors (strides, sparse substitution,
// component types and normalisation), every offset and count range-checked in 128-bit
// arithmetic before a byte is read.
#include <algorithm>
#include <cstring>

#include "scene/gltf/gltf_internal.h"

namespace clpt::gltf {

int type_components(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

namespace {

size_t component_size(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;  // INT and DOUBLE are not glTF 2.0 accessor types
  }
}

const char* component_type_name(int ct) {
  switch (ct) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT: return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_INT: return "INT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return "FLOAT";
    case TINYGLTF_COMPONENT_TYPE_DOUBLE: return "DOUBLE";
    default: return "unknown";
  }
}

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
    default: return "unknown";
  }
}

// One component at p (little-endian host; glTF data is little-endian).
double decode_component(const unsigned char* p, int ct, bool normalized) {
  switch (ct) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? p[0] / 255.0 : p[0];
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: return 0.0;
  }
}

bool small_integer(int ct) {
  return ct == TINYGLTF_COMPONENT_TYPE_BYTE || ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
         ct == TINYGLTF_COMPONENT_TYPE_SHORT || ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
}

uint32_t decode_index(const unsigned char* p, int ct) {
  switch (ct) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return p[0];
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    default: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}
}  // namespace

Converter::ViewBytes Converter::buffer_view(int index, const std::string& user) const {
  if (index < 0 || size_t(index) >= m_.bufferViews.size())
    fail(user + " refers to bufferView " + std::to_string(index) + ", which does not exist (the file has " +
         std::to_string(m_.bufferViews.size()) + ")");
  const tinygltf::BufferView& bv = m_.bufferViews[size_t(index)];
  auto meshopt = bv.extensions.find("EXT_meshopt_compression");
  if (meshopt != bv.extensions.end()) {
    const std::vector<unsigned char>& d = meshopt_view(index, meshopt->second);
    return {d.data(), d.size(), bv.byteStride};
  }
  if (bv.buffer < 0 || size_t(bv.buffer) >= m_.buffers.size())
    fail("bufferView " + std::to_string(index) + " refers to buffer " + std::to_string(bv.buffer) +
         ", which does not exist (the file has " + std::to_string(m_.buffers.size()) + ")");
  const tinygltf::Buffer& buf = m_.buffers[size_t(bv.buffer)];
  const u128 end = u128(bv.byteOffset) + u128(bv.byteLength);
  if (end > u128(buf.data.size()))
    fail("bufferView " + std::to_string(index) + " reads bytes " + std::to_string(bv.byteOffset) + ".." +
         to_string_u128(end) + " past the end of buffer " + std::to_string(bv.buffer) + " (" +
         std::to_string(buf.data.size()) + " bytes)");
  return {buf.data.data() + bv.byteOffset, bv.byteLength, bv.byteStride};
}

Converter::Elements Converter::accessor_elements(int index, const std::string& what, int type,
                                                 Components allowed) const {
  if (index < 0 || size_t(index) >= m_.accessors.size())
    fail(what + " refers to accessor " + std::to_string(index) + ", which does not exist (the file has " +
         std::to_string(m_.accessors.size()) + ")");
  const tinygltf::Accessor& acc = m_.accessors[size_t(index)];
  const std::string desc = accessor_desc(index, what);

  if (acc.type != type)
    fail(desc + " has type " + type_name(acc.type) + ", expected " + type_name(type));
  const int ct = acc.componentType;
  bool ok = false;
  switch (allowed) {
    case Components::Float: ok = ct == TINYGLTF_COMPONENT_TYPE_FLOAT; break;
    case Components::FloatOrUNorm:
      ok = ct == TINYGLTF_COMPONENT_TYPE_FLOAT ||
           (acc.normalized && (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                               ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT));
      break;
    case Components::FloatOrSNorm:
      ok = ct == TINYGLTF_COMPONENT_TYPE_FLOAT ||
           (acc.normalized && (ct == TINYGLTF_COMPONENT_TYPE_BYTE || ct == TINYGLTF_COMPONENT_TYPE_SHORT));
      break;
    case Components::Index:
      ok = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
           ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
      break;
    case Components::Position:
      ok = ct == TINYGLTF_COMPONENT_TYPE_FLOAT || (quantized_ && small_integer(ct));
      break;
    case Components::Direction:
      ok = ct == TINYGLTF_COMPONENT_TYPE_FLOAT ||
           (quantized_ && acc.normalized &&
            (ct == TINYGLTF_COMPONENT_TYPE_BYTE || ct == TINYGLTF_COMPONENT_TYPE_SHORT));
      break;
    case Components::TexCoord:
      ok = ct == TINYGLTF_COMPONENT_TYPE_FLOAT ||
           (acc.normalized && (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                               ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)) ||
           (quantized_ && small_integer(ct));
      break;
  }
  if (!ok)
    fail(desc + " has component type " + component_type_name(ct) + (acc.normalized ? " (normalized)" : "") +
         ", which is not allowed there" +
         (!quantized_ && ct != TINYGLTF_COMPONENT_TYPE_FLOAT &&
                  (allowed == Components::Position || allowed == Components::Direction ||
                   allowed == Components::TexCoord)
              ? " (integer attributes need KHR_mesh_quantization in extensionsUsed)"
              : ""));

  Elements e{&acc, nullptr, 0, acc.count, type_components(type), component_size(ct)};
  const uint64_t elem_size = uint64_t(e.ncomp) * e.comp_size;
  if (acc.count > limits_.accessor_count)
    fail(desc + " has count " + std::to_string(acc.count) + ", more than the limit of " +
         std::to_string(limits_.accessor_count) + " (--limit accessor-count=N)");

  auto decoded = draco_accessors_.find(index);
  if (decoded != draco_accessors_.end()) {
    // Decoded by decode_draco in this accessor's layout: count elements, tightly packed.
    if (decoded->second.size() != acc.count * elem_size)
      fail(desc + ": the Draco data decodes to " + std::to_string(decoded->second.size()) + " bytes, not " +
           std::to_string(acc.count) + " elements of " + std::to_string(elem_size) + " bytes");
    e.data = decoded->second.data();
    e.stride = elem_size;
    return e;
  }
  if (acc.bufferView < 0) {
    // Zeros cost the file nothing, so they are counted over every read (issue 23, class 4: a
    // 1 KB file whose 2^24 zero instances fed EXT_mesh_gpu_instancing took 6.7 GB).
    if (acc.count > limits_.zero_accessor_count - std::min(zero_elements_, limits_.zero_accessor_count))
      fail(desc + " has no bufferView (all zeros) and count " + std::to_string(acc.count) + ": with the " +
           std::to_string(zero_elements_) + " zero elements read before, more than the limit of " +
           std::to_string(limits_.zero_accessor_count) + " (--limit zero-accessor-count=N)");
    zero_elements_ += acc.count;
    return e;  // zeros (then sparse values, if any)
  }
  ViewBytes view = buffer_view(acc.bufferView, desc);
  e.stride = view.stride ? view.stride : elem_size;
  if (e.stride < elem_size)
    fail(desc + " has elements of " + std::to_string(elem_size) + " bytes, but bufferView " +
         std::to_string(acc.bufferView) + " has byteStride " + std::to_string(view.stride));
  if (acc.count > 0) {
    const u128 end = u128(acc.byteOffset) + u128(e.stride) * u128(acc.count - 1) + u128(elem_size);
    if (end > u128(view.length))
      fail(desc + " reads bytes " + std::to_string(acc.byteOffset) + ".." + to_string_u128(end) +
           " past the end of bufferView " + std::to_string(acc.bufferView) + " (" +
           std::to_string(view.length) + " bytes)");
    e.data = view.data + acc.byteOffset;
  }
  return e;
}

// Calls sink(element, component, bytes) for every component of an accessor's data, then again
// for the components that its sparse substitution overrides. Elements of an accessor without a
// bufferView are left to the caller (zeros).
template <class Sink>
void Converter::for_each_component(const Elements& e, int index, const std::string& what, Sink&& sink) const {
  const tinygltf::Accessor& acc = *e.acc;
  const size_t ncomp = size_t(e.ncomp);
  if (e.data) {
    for (uint64_t i = 0; i < e.count; ++i) {
      const unsigned char* p = e.data + i * e.stride;
      for (size_t c = 0; c < ncomp; ++c) sink(size_t(i), c, p + c * e.comp_size);
    }
  }
  if (!acc.sparse.isSparse) return;
  const auto& sp = acc.sparse;
  const std::string desc = accessor_desc(index, what);
  if (sp.count < 1 || uint64_t(sp.count) > e.count)
    fail(desc + " has sparse count " + std::to_string(sp.count) + ", not in 1.." + std::to_string(e.count));
  const int ict = sp.indices.componentType;
  if (ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      ict != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    fail(desc + " has sparse indices of component type " + component_type_name(ict) +
         ", expected UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
  if (sp.indices.byteOffset < 0 || sp.values.byteOffset < 0) fail(desc + " has a negative sparse byteOffset");
  const uint64_t n = uint64_t(sp.count);
  const size_t isize = component_size(ict);
  const uint64_t elem_size = uint64_t(ncomp) * e.comp_size;

  const ViewBytes iview = buffer_view(sp.indices.bufferView, desc + " sparse indices");
  const u128 iend = u128(uint64_t(sp.indices.byteOffset)) + u128(n) * isize;
  if (iend > u128(iview.length))
    fail(desc + " sparse indices read bytes " + std::to_string(sp.indices.byteOffset) + ".." +
         to_string_u128(iend) + " past the end of bufferView " + std::to_string(sp.indices.bufferView) + " (" +
         std::to_string(iview.length) + " bytes)");
  const ViewBytes vview = buffer_view(sp.values.bufferView, desc + " sparse values");
  const u128 vend = u128(uint64_t(sp.values.byteOffset)) + u128(n) * elem_size;
  if (vend > u128(vview.length))
    fail(desc + " sparse values read bytes " + std::to_string(sp.values.byteOffset) + ".." +
         to_string_u128(vend) + " past the end of bufferView " + std::to_string(sp.values.bufferView) + " (" +
         std::to_string(vview.length) + " bytes)");
  const unsigned char* ip = iview.data + sp.indices.byteOffset;
  const unsigned char* vp = vview.data + sp.values.byteOffset;
  for (uint64_t k = 0; k < n; ++k) {
    const uint32_t target = decode_index(ip + k * isize, ict);
    if (target >= e.count)
      fail(desc + " sparse index " + std::to_string(target) + " (entry " + std::to_string(k) +
           ") is not less than its count " + std::to_string(e.count));
    for (size_t c = 0; c < ncomp; ++c) sink(size_t(target), c, vp + k * elem_size + c * e.comp_size);
  }
}

std::vector<float> Converter::read_values(int index, const std::string& what, int type, Components allowed) const {
  const Elements e = accessor_elements(index, what, type, allowed);
  const size_t ncomp = size_t(e.ncomp);
  const int ct = e.acc->componentType;
  const bool normalized = e.acc->normalized;
  std::vector<float> out(size_t(e.count) * ncomp, 0.0f);
  for_each_component(e, index, what, [&](size_t i, size_t c, const unsigned char* p) {
    out[i * ncomp + c] = float(decode_component(p, ct, normalized));
  });
  return out;
}

std::vector<uint32_t> Converter::read_indices(int index, const std::string& what) const {
  const Elements e = accessor_elements(index, what, TINYGLTF_TYPE_SCALAR, Components::Index);
  const int ct = e.acc->componentType;
  std::vector<uint32_t> out(size_t(e.count), 0);
  for_each_component(e, index, what,
                     [&](size_t i, size_t, const unsigned char* p) { out[i] = decode_index(p, ct); });
  return out;
}

}  // namespace clpt::gltf
