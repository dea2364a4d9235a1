// The glTF loader's materials and textures: images (decoded by scene/image_decode from the
// bytes uri.cpp kept or from a checked bufferView; --lenient: a magenta placeholder), samplers,
// textureInfos with KHR_texture_transform, and the metallic-roughness materials with the
// KHR_materials_* extensions clpt supports.
#include <algorithm>
#include <cmath>
#include <limits>

#include "scene/gltf/gltf_internal.h"
#include "util/log.h"

namespace clpt::gltf {

// ---- textures

std::string Converter::image_label(int index) const {
  const tinygltf::Image& gi = m_.images[size_t(index)];
  std::string label = "image " + std::to_string(index);
  if (!gi.name.empty()) label += " " + printable(gi.name);
  else if (!gi.uri.empty() && gi.uri.rfind("data:", 0) != 0) label += " " + printable(gi.uri);
  return label;
}

// The encoded bytes of glTF image `index` (a checked bufferView, or what uri.cpp read), or
// false with the reason.
bool Converter::image_bytes(int index, const unsigned char** data, size_t* size, std::string* why) {
  const tinygltf::Image& gi = m_.images[size_t(index)];
  if (gi.bufferView >= 0) {
    const ViewBytes v = buffer_view(gi.bufferView, image_label(index));
    *data = v.data;
    *size = size_t(v.length);
    return true;
  }
  auto bytes = images_.bytes.find(index);
  if (bytes != images_.bytes.end()) {
    *data = bytes->second.data();
    *size = bytes->second.size();
    return true;
  }
  auto p = images_.problem.find(index);
  *why = p != images_.problem.end() ? p->second : "its data could not be read";
  return false;
}

namespace {

// Per scene texture: whether only normal-map slots (normalTexture, clearcoatNormalTexture) read
// it. Those keep a 16-bit image's 16 bits: an 8-bit normal map's steps of 1/127 in a normal's
// components (0.45 degrees) show as bands in a smooth highlight. Any other slot, or none, gets
// 8 bits (the kernels read either format anywhere).
std::vector<bool> normal_map_only(const Scene& scene) {
  std::vector<uint8_t> uses(scene.textures.size(), 0);  // bit 0: a normal slot, bit 1: another
  auto mark = [&](const TextureRef& r, uint8_t bit) {
    if (r.used() && size_t(r.texture) < uses.size()) uses[size_t(r.texture)] |= bit;
  };
  for (const Material& m : scene.materials) {
    for (const TextureRef* r : {&m.normal_texture, &m.clearcoat_normal_texture}) mark(*r, 1);
    for (const TextureRef* r :
         {&m.base_color_texture, &m.metallic_roughness_texture, &m.emissive_texture, &m.transmission_texture,
          &m.specular_texture, &m.specular_color_texture, &m.clearcoat_texture, &m.clearcoat_roughness_texture,
          &m.iridescence_texture, &m.iridescence_thickness_texture, &m.diffuse_transmission_texture,
          &m.diffuse_transmission_color_texture, &m.sheen_color_texture, &m.sheen_roughness_texture,
          &m.anisotropy_texture})
      mark(*r, 2);
  }
  std::vector<bool> only(uses.size());
  for (size_t i = 0; i < uses.size(); ++i) only[i] = uses[i] == 1;
  return only;
}

}  // namespace

// Decodes every image the materials use into its scene textures, once all materials are known:
// first the sizes their headers give are added up and checked against the limits, so a scene
// whose textures together are too large is refused before any is decoded (issue 23, class 3:
// five 8192 x 8192 PNGs in an 84 KB scene were decoded, 2.5 GB, before the total was
// checked). Each image is decoded once; its last scene texture takes the texels, the others
// (the same image under other sampler settings) copy them.
void Converter::decode_textures() {
  const std::vector<bool> normal_only = normal_map_only(scene_);
  std::map<int, std::vector<int>> users;  // glTF image -> its scene textures
  for (const auto& [id, pending] : pending_textures_) users[pending.source].push_back(id);

  struct Header {
    uint64_t width = 0, height = 0;
    bool known = false;
  };
  std::map<int, Header> headers;
  uint64_t total = 0;
  std::vector<std::pair<uint64_t, int>> largest;  // (texels, image)
  for (const auto& [source, ids] : users) {
    const unsigned char* data = nullptr;
    size_t size = 0;
    std::string why;
    Header h;
    if (image_bytes(source, &data, &size, &why)) h.known = image_header_size(data, size, &h.width, &h.height);
    headers[source] = h;
    if (!h.known) continue;  // decode_image says what is wrong with it
    const u128 texels = u128(h.width) * h.height * ids.size();
    total = texels > u128(~uint64_t{0} - total) ? ~uint64_t{0} : total + uint64_t(texels);
    largest.emplace_back(uint64_t(std::min<u128>(texels, ~uint64_t{0})), source);
  }
  if (total > limits_.total_texels && !images_.lenient) {
    std::stable_sort(largest.begin(), largest.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<std::string> names;
    for (size_t i = 0; i < largest.size() && i < 3; ++i) {
      const Header& h = headers[largest[i].second];
      names.push_back(image_label(largest[i].second) + " " + std::to_string(h.width) + "x" + std::to_string(h.height));
    }
    fail("the images the materials use are " + std::to_string(total) + " texels together (" + join(names, ", ") +
         (largest.size() > 3 ? ", ..." : "") + "), more than the limit of " + std::to_string(limits_.total_texels) +
         " (--limit total-texels=N)");
  }

  for (const auto& [source, ids] : users) {
    const std::string label = image_label(source);
    const std::string where = "used by " + pending_textures_.at(ids.front()).where;
    DecodedImage img;
    std::string why;
    bool ok = false;
    const Header& h = headers[source];
    const uint64_t copies = ids.size();
    // The textures that read the image as a normal map alone: they keep a 16-bit image's 16 bits.
    const uint64_t normal_users =
        uint64_t(std::count_if(ids.begin(), ids.end(), [&](int id) { return normal_only[size_t(id)]; }));
    // Whether `units` textures' worth of w x h texels are left under total-texels.
    auto room = [&](uint64_t w, uint64_t hh, uint64_t units) {
      return u128(w) * hh * units <= u128(limits_.total_texels - total_texels_);
    };
    // Whether `copies` textures of w x h would pass total-texels, with `why` set when not.
    auto fits = [&](uint64_t w, uint64_t hh) {
      if (room(w, hh, copies)) return true;
      why = "with it the images the materials use exceed the limit of " + std::to_string(limits_.total_texels) +
            " texels (--limit total-texels=N)";
      return false;
    };
    if (!h.known || fits(h.width, h.height)) {
      const unsigned char* data = nullptr;
      size_t size = 0;
      if (image_bytes(source, &data, &size, &why))
        ok = decode_image(data, size, &img, &why, limits_.image_dimension, limits_.image_pixels,
                          normal_users > 0);
      images_.bytes.erase(source);  // decoded once; the encoded copy is no longer needed
      ok = ok && fits(img.width, img.height);  // a JPEG whose frame size only the decoder knew (DNL)
      // A 16-bit normal map's texel takes two words: it counts twice. Where that would pass the
      // limit and 8 bits would not, the map is kept at 8 bits (as before 16-bit maps).
      if (ok && img.wide && !room(img.width, img.height, copies + normal_users)) {
        log::warn(display_ + ": " + label + " (" + where + ") is kept at 8 bits a channel: at 16 its texels " +
                  "would exceed the limit of " + std::to_string(limits_.total_texels) +
                  " texels (--limit total-texels=N; a 16-bit texel counts twice)");
        img.texels = narrow_texels(img.texels);
        img.wide = false;
      }
    }
    if (!ok) {
      if (!images_.lenient) fail(label + " (" + where + "): " + why + " (--lenient: warn and use a magenta texture)");
      log::warn(display_ + ": " + label + " (" + where + "): " + why + "; using a magenta texture");
      img = placeholder_image();
    }
    for (size_t k = 0; k < ids.size(); ++k) {
      Texture& t = scene_.textures[size_t(ids[k])];
      t.width = img.width;
      t.height = img.height;
      t.wide = img.wide && normal_only[size_t(ids[k])];  // the image under another sampler
      total_texels_ += uint64_t(img.width) * img.height * (t.wide ? 2u : 1u);
      if (img.wide && !t.wide) t.texels = narrow_texels(img.texels);
      else if (k + 1 < ids.size()) t.texels = img.texels;
      else t.texels = std::move(img.texels);
    }
  }
  pending_textures_.clear();
}

// The scene texture for glTF texture `texture` (decoded image + its sampler), or -1 when the
// texture has no image clpt can use. Textures with the same image and sampler settings share.
int Converter::scene_texture(int texture, const std::string& where) {
  if (texture < 0 || size_t(texture) >= m_.textures.size())
    fail(where + " refers to texture " + std::to_string(texture) + ", which does not exist (the file has " +
         std::to_string(m_.textures.size()) + ")");
  auto known = texture_of_.find(texture);
  if (known != texture_of_.end()) return known->second;
  const tinygltf::Texture& gt = m_.textures[size_t(texture)];
  const std::string tdesc = "texture " + std::to_string(texture);
  // The image: EXT_texture_webp's source when there is one (WebP decodes through OpenImageIO),
  // else the core source (KHR_texture_basisu's KTX2 source cannot be decoded: its core source
  // is the fallback the extension defines).
  int source = gt.source;
  auto webp = gt.extensions.find("EXT_texture_webp");
  if (webp != gt.extensions.end()) {
    if (!webp->second.IsObject() || !webp->second.Has("source") || !webp->second.Get("source").IsInt())
      fail(tdesc + " EXT_texture_webp has no integer source");
    source = webp->second.Get("source").GetNumberAsInt();
  }
  if (source < 0) {
    log::warn(display_ + ": " + tdesc + " has no PNG, JPEG or WebP source (e.g. only a KTX2 one); " + where +
              " is rendered without it");
    return texture_of_[texture] = -1;
  }
  if (size_t(source) >= m_.images.size())
    fail(tdesc + " refers to image " + std::to_string(source) + ", which does not exist (the file has " +
         std::to_string(m_.images.size()) + ")");
  Texture::Wrap ws = Texture::Wrap::Repeat, wt = Texture::Wrap::Repeat;
  bool nearest = false;
  if (gt.sampler >= 0) {
    if (size_t(gt.sampler) >= m_.samplers.size())
      fail(tdesc + " refers to sampler " + std::to_string(gt.sampler) + ", which does not exist (the file has " +
           std::to_string(m_.samplers.size()) + ")");
    const tinygltf::Sampler& sm = m_.samplers[size_t(gt.sampler)];
    auto wrap = [&](int mode, const char* name) {
      switch (mode) {
        case TINYGLTF_TEXTURE_WRAP_REPEAT: return Texture::Wrap::Repeat;
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return Texture::Wrap::Clamp;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return Texture::Wrap::Mirror;
        default:
          log::warn(display_ + ": sampler " + std::to_string(gt.sampler) + " has " + name + " " +
                    std::to_string(mode) + ", not a glTF wrap mode; using REPEAT");
          return Texture::Wrap::Repeat;
      }
    };
    ws = wrap(sm.wrapS, "wrapS");
    wt = wrap(sm.wrapT, "wrapT");
    nearest = sm.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
  }
  const auto key = std::make_tuple(source, int(ws), int(wt), nearest);
  auto shared = textures_.find(key);
  if (shared != textures_.end()) return texture_of_[texture] = shared->second;
  Texture t;  // its texels come from decode_textures, once every material is known
  const tinygltf::Image& gi = m_.images[size_t(source)];
  t.name = !gi.name.empty() ? gi.name : (!gi.uri.empty() && gi.uri.rfind("data:", 0) != 0 ? gi.uri
                                                                                          : "image " + std::to_string(source));
  t.wrap_s = ws;
  t.wrap_t = wt;
  t.nearest = nearest;
  const int id = int(scene_.textures.size());
  scene_.textures.push_back(std::move(t));
  pending_textures_.emplace(id, PendingTexture{source, where});
  textures_.emplace(key, id);
  return texture_of_[texture] = id;
}

// A textureInfo: texture, UV set and KHR_texture_transform (offset, rotation, scale, texCoord
// override) folded into uv' = T * R * S * (u, v, 1), as the extension defines it.
TextureRef Converter::texture_ref(int index, int texcoord, const tinygltf::Value* transform,
                                  const std::string& where) {
  TextureRef ref;
  if (index < 0) return ref;
  double ox = 0, oy = 0, rot = 0, sx = 1, sy = 1;
  if (transform) {
    const std::string tw = where + " KHR_texture_transform";
    if (!transform->IsObject()) fail(tw + " is not an object");
    auto vec2 = [&](const char* key, double* x, double* y) {
      if (!transform->Has(key)) return;
      const tinygltf::Value& v = transform->Get(key);
      if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber())
        fail(tw + " " + key + " is not an array of 2 numbers");
      *x = v.Get(0).GetNumberAsDouble();
      *y = v.Get(1).GetNumberAsDouble();
      if (!std::isfinite(*x) || !std::isfinite(*y)) fail(tw + " " + key + " is not finite");
    };
    vec2("offset", &ox, &oy);
    vec2("scale", &sx, &sy);
    if (transform->Has("rotation")) {
      const tinygltf::Value& r = transform->Get("rotation");
      if (!r.IsNumber() || !std::isfinite(r.GetNumberAsDouble())) fail(tw + " rotation is not a finite number");
      rot = r.GetNumberAsDouble();
    }
    if (transform->Has("texCoord")) {
      const tinygltf::Value& t = transform->Get("texCoord");
      if (!t.IsInt()) fail(tw + " texCoord is not an integer");
      texcoord = t.GetNumberAsInt();
    }
  }
  if (texcoord != 0 && texcoord != 1) {
    const std::string msg = where + " uses texCoord " + std::to_string(texcoord) +
                            "; clpt reads TEXCOORD_0 and TEXCOORD_1 only";
    if (!images_.lenient) fail(msg + " (--lenient: use TEXCOORD_0)");
    log::warn(display_ + ": " + msg + "; using TEXCOORD_0");
    texcoord = 0;
  }
  ref.texture = scene_texture(index, where);
  if (ref.texture < 0) return TextureRef{};
  ref.texcoord = uint32_t(texcoord);
  const double c = std::cos(rot), s = std::sin(rot);
  // glm::mat3x2: column 0 multiplies u, column 1 v, column 2 is the offset.
  ref.transform = glm::mat3x2(glm::vec2(float(sx * c), float(-sx * s)), glm::vec2(float(sy * s), float(sy * c)),
                              glm::vec2(float(ox), float(oy)));
  return ref;
}

// A textureInfo inside an extension (a JSON value tinygltf does not interpret).
TextureRef Converter::texture_info(const tinygltf::Value& info, const std::string& where) {
  if (!info.IsObject()) fail(where + " is not an object");
  if (!info.Has("index") || !info.Get("index").IsInt()) fail(where + " has no integer index");
  const int index = info.Get("index").GetNumberAsInt();
  int texcoord = 0;
  if (info.Has("texCoord")) {
    if (!info.Get("texCoord").IsInt()) fail(where + " texCoord is not an integer");
    texcoord = info.Get("texCoord").GetNumberAsInt();
  }
  const tinygltf::Value* transform = nullptr;
  if (info.Has("extensions") && info.Get("extensions").IsObject() &&
      info.Get("extensions").Has("KHR_texture_transform"))
    transform = &info.Get("extensions").Get("KHR_texture_transform");
  if (index < 0)
    fail(where + " refers to texture " + std::to_string(index) + ", which does not exist (the file has " +
         std::to_string(m_.textures.size()) + ")");
  return texture_ref(index, texcoord, transform, where);
}

// ---- materials

namespace {
const tinygltf::Value* find_extension(const tinygltf::ExtensionMap& ext, const char* name) {
  auto it = ext.find(name);
  return it == ext.end() ? nullptr : &it->second;
}
}  // namespace

void Converter::convert_materials() {
  scene_.materials.reserve(m_.materials.size() + 1);
  size_t occlusion = 0;
  for (size_t i = 0; i < m_.materials.size(); ++i) {
    const tinygltf::Material& gm = m_.materials[i];
    const std::string where = "material " + std::to_string(i);
    Material mat;
    mat.name = gm.name;
    const auto& pbr = gm.pbrMetallicRoughness;
    auto check = [&](double v, const char* field) {
      if (!std::isfinite(v)) fail(where + " has a non-finite " + field);
      return v;
    };
    // A textureInfo of the core material.
    auto core_texture = [&](int index, int texcoord, const tinygltf::ExtensionMap& ext, const char* name) {
      return texture_ref(index, texcoord, find_extension(ext, "KHR_texture_transform"), where + " " + name);
    };
    // The members of an extension object.
    auto ext_number = [&](const tinygltf::Value& e, const char* ext_name, const char* key, double def) {
      if (!e.Has(key)) return def;
      const tinygltf::Value& v = e.Get(key);
      if (!v.IsNumber()) fail(where + " " + ext_name + " " + key + " is not a number");
      const double d = v.GetNumberAsDouble();
      if (!std::isfinite(d)) fail(where + " " + ext_name + " " + key + " is not finite");
      return d;
    };
    auto ext_color = [&](const tinygltf::Value& e, const char* ext_name, const char* key,
                         glm::vec3 def = glm::vec3(1.0f)) {
      glm::vec3 c = def;
      if (!e.Has(key)) return c;
      const tinygltf::Value& v = e.Get(key);
      if (!v.IsArray() || v.ArrayLen() != 3) fail(where + " " + ext_name + " " + key + " is not an array of 3 numbers");
      for (int k = 0; k < 3; ++k) {
        if (!v.Get(k).IsNumber() || !std::isfinite(v.Get(k).GetNumberAsDouble()))
          fail(where + " " + ext_name + " " + key + " is not an array of 3 finite numbers");
        c[k] = float(std::max(v.Get(k).GetNumberAsDouble(), 0.0));
      }
      return c;
    };
    auto ext_texture = [&](const tinygltf::Value& e, const char* ext_name, const char* key) {
      if (!e.Has(key)) return TextureRef{};
      return texture_info(e.Get(key), where + " " + ext_name + " " + key);
    };
    auto extension = [&](const char* name) -> const tinygltf::Value* {
      const tinygltf::Value* e = find_extension(gm.extensions, name);
      if (e && !e->IsObject()) fail(where + " " + name + " is not an object");
      return e;
    };

    if (pbr.baseColorFactor.size() == 4)
      for (int c = 0; c < 4; ++c)
        mat.base_color[c] = float(std::clamp(check(pbr.baseColorFactor[size_t(c)], "baseColorFactor"), 0.0, 1.0));
    mat.metallic = float(std::clamp(check(pbr.metallicFactor, "metallicFactor"), 0.0, 1.0));
    mat.roughness = float(std::clamp(check(pbr.roughnessFactor, "roughnessFactor"), 0.0, 1.0));
    mat.base_color_texture = core_texture(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                                          pbr.baseColorTexture.extensions, "baseColorTexture");
    mat.metallic_roughness_texture =
        core_texture(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                     pbr.metallicRoughnessTexture.extensions, "metallicRoughnessTexture");
    mat.normal_texture = core_texture(gm.normalTexture.index, gm.normalTexture.texCoord,
                                      gm.normalTexture.extensions, "normalTexture");
    if (mat.normal_texture.used()) mat.normal_scale = float(check(gm.normalTexture.scale, "normalTexture.scale"));
    mat.emissive_texture = core_texture(gm.emissiveTexture.index, gm.emissiveTexture.texCoord,
                                        gm.emissiveTexture.extensions, "emissiveTexture");
    if (gm.occlusionTexture.index >= 0) ++occlusion;

    double strength = 1.0;
    if (const tinygltf::Value* e = extension("KHR_materials_emissive_strength")) {
      strength = ext_number(*e, "KHR_materials_emissive_strength", "emissiveStrength", 1.0);
      if (strength < 0) fail(where + " has a negative emissiveStrength " + number(strength));
    }
    if (gm.emissiveFactor.size() == 3)
      for (int c = 0; c < 3; ++c) {
        double e = std::max(check(gm.emissiveFactor[size_t(c)], "emissiveFactor"), 0.0) * strength;
        if (!std::isfinite(float(e))) fail(where + " has an emission too large for a float");
        mat.emission[c] = float(e);
      }
    mat.double_sided = gm.doubleSided;

    if (gm.alphaMode == "MASK") {
      mat.alpha_mode = Material::AlphaMode::Mask;
    } else if (gm.alphaMode == "BLEND") {
      mat.alpha_mode = Material::AlphaMode::Blend;
    } else if (!gm.alphaMode.empty() && gm.alphaMode != "OPAQUE") {
      log::warn(display_ + ": " + where + " has alphaMode " + printable(gm.alphaMode) + "; treated as OPAQUE");
    }
    mat.alpha_cutoff = float(check(gm.alphaCutoff, "alphaCutoff"));

    if (const tinygltf::Value* e = extension("KHR_materials_transmission")) {
      const char* n = "KHR_materials_transmission";
      mat.transmission = float(std::clamp(ext_number(*e, n, "transmissionFactor", 0.0), 0.0, 1.0));
      mat.transmission_texture = ext_texture(*e, n, "transmissionTexture");
    }
    if (const tinygltf::Value* e = extension("KHR_materials_ior")) {
      const double ior = ext_number(*e, "KHR_materials_ior", "ior", 1.5);
      // The extension allows 0 ("no refraction"); clpt keeps indices in [1, 10].
      mat.ior = float(std::clamp(ior, 1.0, 10.0));
    }
    if (const tinygltf::Value* e = extension("KHR_materials_specular")) {
      const char* n = "KHR_materials_specular";
      mat.specular = float(std::clamp(ext_number(*e, n, "specularFactor", 1.0), 0.0, 1.0));
      mat.specular_color = ext_color(*e, n, "specularColorFactor");
      mat.specular_texture = ext_texture(*e, n, "specularTexture");
      mat.specular_color_texture = ext_texture(*e, n, "specularColorTexture");
    }
    if (const tinygltf::Value* e = extension("KHR_materials_clearcoat")) {
      const char* n = "KHR_materials_clearcoat";
      mat.clearcoat = float(std::clamp(ext_number(*e, n, "clearcoatFactor", 0.0), 0.0, 1.0));
      mat.clearcoat_roughness = float(std::clamp(ext_number(*e, n, "clearcoatRoughnessFactor", 0.0), 0.0, 1.0));
      mat.clearcoat_texture = ext_texture(*e, n, "clearcoatTexture");
      mat.clearcoat_roughness_texture = ext_texture(*e, n, "clearcoatRoughnessTexture");
      mat.clearcoat_normal_texture = ext_texture(*e, n, "clearcoatNormalTexture");
      if (mat.clearcoat_normal_texture.used()) {
        const tinygltf::Value& info = e->Get("clearcoatNormalTexture");
        mat.clearcoat_normal_scale = float(ext_number(info, "KHR_materials_clearcoat clearcoatNormalTexture", "scale", 1.0));
      }
    }
    if (const tinygltf::Value* e = extension("KHR_materials_iridescence")) {
      const char* n = "KHR_materials_iridescence";
      mat.iridescence = float(std::clamp(ext_number(*e, n, "iridescenceFactor", 0.0), 0.0, 1.0));
      // The film's index: the extension's minimum is 1; clpt keeps [1, 10] as for KHR_materials_ior.
      mat.iridescence_ior = float(std::clamp(ext_number(*e, n, "iridescenceIor", 1.3), 1.0, 10.0));
      // Thicknesses in nm, >= 0 by the schema. Past a few um the interference terms vanish
      // (thin_film_fringes' Gaussians), so the 1e5 nm cap changes nothing visible.
      const double t_min = ext_number(*e, n, "iridescenceThicknessMinimum", 100.0);
      const double t_max = ext_number(*e, n, "iridescenceThicknessMaximum", 400.0);
      mat.iridescence_thickness_min = float(std::clamp(t_min, 0.0, 1e5));
      mat.iridescence_thickness_max = float(std::clamp(t_max, 0.0, 1e5));
      mat.iridescence_texture = ext_texture(*e, n, "iridescenceTexture");
      mat.iridescence_thickness_texture = ext_texture(*e, n, "iridescenceThicknessTexture");
    }
    if (const tinygltf::Value* e = extension("KHR_materials_diffuse_transmission")) {
      const char* n = "KHR_materials_diffuse_transmission";
      mat.diffuse_transmission = float(std::clamp(ext_number(*e, n, "diffuseTransmissionFactor", 0.0), 0.0, 1.0));
      mat.diffuse_transmission_texture = ext_texture(*e, n, "diffuseTransmissionTexture");
      mat.diffuse_transmission_color = glm::min(ext_color(*e, n, "diffuseTransmissionColorFactor"), glm::vec3(1.0f));
      mat.diffuse_transmission_color_texture = ext_texture(*e, n, "diffuseTransmissionColorTexture");
    }
    if (const tinygltf::Value* e = extension("KHR_materials_sheen")) {
      const char* n = "KHR_materials_sheen";
      mat.sheen_color = glm::clamp(ext_color(*e, n, "sheenColorFactor", glm::vec3(0.0f)), 0.0f, 1.0f);
      mat.sheen_roughness = float(std::clamp(ext_number(*e, n, "sheenRoughnessFactor", 0.0), 0.0, 1.0));
      mat.sheen_color_texture = ext_texture(*e, n, "sheenColorTexture");
      mat.sheen_roughness_texture = ext_texture(*e, n, "sheenRoughnessTexture");
    }
    if (const tinygltf::Value* e = extension("KHR_materials_dispersion")) {
      // 20 / Abbe number; it bends light only where the glass refracts (walk_disperse).
      mat.dispersion = float(std::clamp(ext_number(*e, "KHR_materials_dispersion", "dispersion", 0.0), 0.0, 1e3));
    }
    if (const tinygltf::Value* e = extension("KHR_materials_anisotropy")) {
      const char* n = "KHR_materials_anisotropy";
      mat.anisotropy_strength = float(std::clamp(ext_number(*e, n, "anisotropyStrength", 0.0), 0.0, 1.0));
      // Radians, counter-clockwise from the tangent; any finite angle.
      mat.anisotropy_rotation = float(std::remainder(ext_number(*e, n, "anisotropyRotation", 0.0), 2.0 * M_PI));
      mat.anisotropy_texture = ext_texture(*e, n, "anisotropyTexture");
    }
    if (const tinygltf::Value* e = extension("KHR_materials_volume")) {
      const char* n = "KHR_materials_volume";
      const double inf = std::numeric_limits<double>::infinity();
      double dist = inf;
      if (e->Has("attenuationDistance")) {
        dist = ext_number(*e, n, "attenuationDistance", inf);
        if (!(dist > 0.0)) fail(where + " " + n + " attenuationDistance " + number(dist) + " is not positive");
      }
      mat.attenuation_distance = float(dist);
      mat.attenuation_color = glm::clamp(ext_color(*e, n, "attenuationColor"), 0.0f, 1.0f);
      mat.volume = std::isfinite(mat.attenuation_distance);
    }
    scene_.materials.push_back(std::move(mat));
  }
  if (occlusion > 0)
    log::verbose(display_ + ": " + std::to_string(occlusion) +
                 " material(s) have an occlusion texture; ignored (a path tracer computes occlusion)");
  decode_textures();
}

uint32_t Converter::material_for(int gltf_material, const std::string& where) {
  if (gltf_material >= 0) {
    if (size_t(gltf_material) >= m_.materials.size())
      fail(where + " refers to material " + std::to_string(gltf_material) +
           ", which does not exist (the file has " + std::to_string(m_.materials.size()) + ")");
    return uint32_t(gltf_material);
  }
  if (default_material_ < 0) {
    Material def;  // glTF defaults: base colour 1, metallic 1, roughness 1
    def.name = "default";
    default_material_ = int(scene_.materials.size());
    scene_.materials.push_back(def);
  }
  return uint32_t(default_material_);
}

}  // namespace clpt::gltf
