#include "scene/tangents.h"

#include <cmath>

namespace clpt {

std::vector<glm::vec4> generate_tangents(const std::vector<glm::vec3>& positions,
                                         const std::vector<glm::vec3>& normals,
                                         const std::vector<glm::vec2>& uvs,
                                         const std::vector<glm::uvec3>& triangles) {
  const size_t n = positions.size();
  std::vector<glm::dvec3> tan(n, glm::dvec3(0.0)), bit(n, glm::dvec3(0.0)), face_n(n, glm::dvec3(0.0));
  for (const glm::uvec3& t : triangles) {
    if (t.x >= n || t.y >= n || t.z >= n || t.x >= uvs.size() || t.y >= uvs.size() || t.z >= uvs.size())
      continue;
    const glm::dvec3 p0 = positions[t.x], p1 = positions[t.y], p2 = positions[t.z];
    const glm::dvec2 w0 = uvs[t.x], w1 = uvs[t.y], w2 = uvs[t.z];
    const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0;
    const glm::dvec2 d1 = w1 - w0, d2 = w2 - w0;
    const glm::dvec3 fn = glm::cross(e1, e2);  // area-weighted face normal
    for (unsigned v : {t.x, t.y, t.z}) face_n[v] += fn;
    const double r = d1.x * d2.y - d2.x * d1.y;
    if (!(std::fabs(r) > 1e-20) || !std::isfinite(r)) continue;
    // dP/du and dP/dv; weighted by the triangle's UV area (|r|), so small slivers count less.
    const glm::dvec3 dpdu = (e1 * d2.y - e2 * d1.y) / r;
    const glm::dvec3 dpdv = (e2 * d1.x - e1 * d2.x) / r;
    const double weight = std::fabs(r);
    if (!std::isfinite(glm::dot(dpdu, dpdu)) || !std::isfinite(glm::dot(dpdv, dpdv))) continue;
    for (unsigned v : {t.x, t.y, t.z}) {
      tan[v] += dpdu * weight;
      bit[v] -= dpdv * weight;  // the image's "up" is decreasing v
    }
  }
  std::vector<glm::vec4> out(n, glm::vec4(0.0f));
  for (size_t i = 0; i < n; ++i) {
    glm::dvec3 nrm = i < normals.size() ? glm::dvec3(normals[i]) : glm::dvec3(0.0);
    if (!(glm::dot(nrm, nrm) > 0.0)) nrm = face_n[i];
    const double nl = glm::length(nrm);
    if (!(nl > 0.0) || !std::isfinite(nl)) continue;
    nrm /= nl;
    glm::dvec3 t = tan[i] - nrm * glm::dot(nrm, tan[i]);
    const double tl = glm::length(t);
    if (!(tl > 1e-12) || !std::isfinite(tl)) continue;
    t /= tl;
    const double w = glm::dot(glm::cross(nrm, t), bit[i]) < 0.0 ? -1.0 : 1.0;
    out[i] = glm::vec4(glm::vec3(t), float(w));
  }
  return out;
}

}  // namespace clpt
