// Meshes a case body by body with gmsh (one gmsh session per call) and computes the mesh
// signature used to detect stale models. Verified by tests/mesher/mesher_test.cpp.
#include "mesher/mesher.hpp"

#include "mesher/gmsh_body.hpp"
#include "solver/core/error.hpp"

#include <gmsh.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <charconv>
#include <cmath>
#include <set>
#include <sstream>

namespace sphfem {
namespace {

// gmsh is process-global: initialise quietly without reading user configuration files, and
// finalise even when meshing throws. gmsh 4.8 reports errors by throwing std::string.
// gmsh also sets the OpenMP thread count (General.NumThreads = 1): the solver's is restored.
class GmshSession {
public:
  GmshSession() {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
  }
  ~GmshSession() {
    gmsh::finalize();
#ifdef _OPENMP
    omp_set_num_threads(threads_);
#endif
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

private:
#ifdef _OPENMP
  int threads_ = omp_get_max_threads();
#endif
};

mesher::Placement build_body(const BodySpec& body) {
  SPHFEM_CHECK(body.element_size > 0 && std::isfinite(body.element_size),
               "element_size must be positive, got ", body.element_size);
  switch (body.geometry.kind) {
  case GeometrySpec::Kind::Box:
    return mesher::build_box(body);
  case GeometrySpec::Kind::Cylinder:
    return mesher::build_cylinder(body);
  }
  throw Error("unknown geometry kind");
}

void mesh_body(Model& model, const BodySpec& body, int body_id) {
  try {
    gmsh::clear();
    gmsh::model::add(body.name);
    const mesher::Placement placement = build_body(body);
    gmsh::model::mesh::generate(3);
    mesher::append_mesh(model, body_id, placement);
  } catch (const std::string& gmsh_error) {
    throw Error(detail::concat("mesh: body '", body.name, "': gmsh: ", gmsh_error));
  } catch (const Error& e) {
    throw Error(detail::concat("mesh: body '", body.name, "': ", e.what()));
  }
}

// Shortest text that reads back to the same double.
std::string exact(double v) {
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, v).ptr;
  return std::string(buffer, end);
}

std::string exact(const Vec3& v) {
  return exact(v.x()) + "," + exact(v.y()) + "," + exact(v.z());
}

std::string method_name(Method method) {
  switch (method) {
  case Method::Fem:
    return "fem";
  }
  return "unknown";
}

std::string geometry_signature(const GeometrySpec& g) {
  switch (g.kind) {
  case GeometrySpec::Kind::Box:
    return "box min=" + exact(g.box.min) + " max=" + exact(g.box.max);
  case GeometrySpec::Kind::Cylinder:
    return "cylinder base=" + exact(g.cylinder.base) + " axis=" + exact(g.cylinder.axis) +
           " radius=" + exact(g.cylinder.radius);
  }
  return "unknown";
}

} // namespace

namespace mesher {

int divisions(double length, double element_size) {
  const double n = length / element_size;
  SPHFEM_CHECK(n < 1e6, "element_size ", element_size, " m gives ", n, " elements across ", length,
               " m");
  return std::max(1, static_cast<int>(std::lround(n)));
}

void add_named_face(const std::string& name, const std::vector<int>& surfaces) {
  const int group = gmsh::model::addPhysicalGroup(2, surfaces);
  gmsh::model::setPhysicalName(2, group, name);
}

} // namespace mesher

Model mesh_case(const Case& c) {
  std::set<std::string> names;
  for (const BodySpec& body : c.bodies)
    SPHFEM_CHECK(names.insert(body.name).second, "mesh: body name '", body.name, "' is used twice");
  Model model;
  model.signature = mesh_signature(c);
  const GmshSession session;
  for (std::size_t b = 0; b < c.bodies.size(); ++b) {
    mesh_body(model, c.bodies[b], static_cast<int>(b));
    model.body_names.push_back(c.bodies[b].name);
  }
  return model;
}

std::string mesh_signature(const Case& c) {
  std::ostringstream out;
  out << "sphfem-mesh 1\n";
  for (const BodySpec& body : c.bodies)
    out << "body " << body.name << " method=" << method_name(body.method) << ' '
        << geometry_signature(body.geometry) << " element_size=" << exact(body.element_size)
        << '\n';
  return out.str();
}

} // namespace sphfem
