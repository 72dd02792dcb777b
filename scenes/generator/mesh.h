// Triangle meshes for the procedural scenes: quads from corner lists, icospheres, and helpers
// that fix the winding so that front faces (counter-clockwise, glTF 2.0 section 3.7.2.1) point
// where the scene needs them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace pmcr::scenegen {

struct Mesh {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;  // empty: flat shading (the geometric normal)
    std::vector<glm::vec2> uvs;      // empty: none (TEXCOORD_0; (0, 0) the image's top-left)
    std::vector<uint32_t> indices;   // three per triangle

    size_t triangleCount() const { return indices.size() / 3; }
    glm::dvec3 geometricNormal(size_t triangle) const;  // cross(p1 - p0, p2 - p0), unnormalized
    glm::dvec3 centroid(size_t triangle) const;
};

// Quads given as consecutive groups of four corners (in order around the quad), each split
// into triangles (0, 1, 2) and (0, 2, 3).
Mesh quads(std::string name, const std::vector<glm::vec3>& corners);

// A geodesic sphere: an icosahedron subdivided `subdivisions` times (20 * 4^n triangles), its
// vertices projected onto the sphere. With smooth == true every vertex carries its exact radial
// normal (pointing out, or in when inward == true); otherwise the mesh has no normals.
// inward == true turns the front faces towards the centre.
Mesh icosphere(std::string name, const glm::dvec3& center, double radius, int subdivisions,
               bool smooth, bool inward);

// Flip triangles whose front face points away from (towards, when away == true) `point`.
void orientTowards(Mesh& mesh, const glm::dvec3& point, bool away);

// Flip triangles whose front face does not point along `direction`.
void orientAlong(Mesh& mesh, const glm::dvec3& direction);

// Flip triangles whose front face points against the sum of their vertex normals.
void orientByNormals(Mesh& mesh);

// Appends `other`'s vertices and triangles; both must have normals or neither.
void append(Mesh& mesh, const Mesh& other);

// A torus around the vertical line through `center`: the tube's centre circle has radius
// `majorRadius`, the tube radius `minorRadius`. Closed, smooth (exact normals), front faces out.
Mesh torus(std::string name, const glm::dvec3& center, double majorRadius, double minorRadius,
           int majorSegments, int minorSegments);

// A solid dome: the upper half of the spherical shell between `innerRadius` and `outerRadius`
// around `center`, closed by the flat ring between them in the plane y = center.y. Closed,
// smooth (radial normals, out of the solid: away from the centre on the outer sphere, towards it
// on the inner one; -y on the ring), front faces out of the solid.
Mesh domeShell(std::string name, const glm::dvec3& center, double outerRadius, double innerRadius,
               int segments, int rings);

// The side of a vertical cylinder from `base` up by `height`: smooth, front faces out.
Mesh cylinderSide(std::string name, const glm::dvec3& base, double radius, double height,
                  int segments);

// The side of a vertical truncated cone, open at both ends: radius `bottomRadius` at `base`,
// `topRadius` at `height` above it. Smooth (normals perpendicular to the slant), front faces out.
Mesh coneSide(std::string name, const glm::dvec3& base, double bottomRadius, double topRadius,
              double height, int segments);

// An axis-aligned box between corners `lo` and `hi`: 12 flat triangles, closed, front faces out.
Mesh box(std::string name, const glm::dvec3& lo, const glm::dvec3& hi);

// A flat regular polygon of `segments` sides in the plane y = center.y, front face up or down.
Mesh disk(std::string name, const glm::dvec3& center, double radius, int segments, bool up);

// A quad centred at `center` with edge vectors `u` and `v` (half of each on either side), front
// face along cross(u, v).
Mesh rectangle(std::string name, const glm::dvec3& center, const glm::dvec3& u,
               const glm::dvec3& v);

// A flat-shaded tube of `sides` sides along a polyline, open at both ends.
Mesh tube(std::string name, const std::vector<glm::dvec3>& path, double radius, int sides);

}  // namespace pmcr::scenegen
