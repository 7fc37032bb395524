// Meshes a case body by body: FE bodies with gmsh, SPH bodies as particle lattices (one gmsh
// session per call, opened only if a body needs it), and computes the mesh signature used to
// detect stale models. Verified by tests/mesher/mesher_test.cpp.
#include "mesher/mesher.hpp"

#include "mesher/gmsh_body.hpp"
#include "mesher/interface_tags.hpp"
#include "mesher/lattice.hpp"
#include "solver/core/error.hpp"

#include <gmsh.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <memory>
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
  case GeometrySpec::Kind::Ring:
    return mesher::build_ring(body);
  case GeometrySpec::Kind::File:
    throw Error("a geometry file can only be filled with particles (method sph)");
  }
  throw Error("unknown geometry kind");
}

bool reads_file(const BodySpec& body) {
  return body.geometry.kind == GeometrySpec::Kind::File;
}

bool needs_gmsh(const BodySpec& body) {
  return body.method == Method::Fem || reads_file(body);
}

// Hexahedra and named faces for an FE body, particles for an SPH body.
void mesh_body(Model& model, const Case& c, const BodySpec& body, int body_id) {
  try {
    if (body.method == Method::Sph) {
      mesher::append_particles(model, body_id, body, c.material(body.material).density);
      model.spacing_b.push_back(body.spacing);
      return;
    }
    gmsh::clear();
    gmsh::model::add(body.name);
    const mesher::Placement placement = build_body(body);
    gmsh::model::mesh::generate(3);
    if (placement.finish)
      placement.finish();
    mesher::append_mesh(model, body_id, placement);
    model.spacing_b.push_back(0);
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
  case Method::Sph:
    return "sph";
  }
  return "unknown";
}

// 64-bit FNV-1a hash of a file's bytes, in hex.
std::string content_hash(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  SPHFEM_CHECK(in, "cannot read geometry file ", file.string());
  std::uint64_t hash = 14695981039346656037ull;
  char buffer[65536];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    for (std::streamsize i = 0; i < in.gcount(); ++i)
      hash = (hash ^ static_cast<unsigned char>(buffer[i])) * 1099511628211ull;
  }
  std::ostringstream out;
  out << std::hex << hash;
  return out.str();
}

std::string sector_name(Sector sector) {
  return sector == Sector::Quarter ? "quarter" : sector == Sector::Half ? "half" : "full";
}

// A pointed nose's shape and parameters; empty for a flat one (so flat cylinders keep their text).
std::string nose_signature(const NoseGeometry& nose) {
  switch (nose.shape) {
  case NoseGeometry::Shape::Flat:
    return "";
  case NoseGeometry::Shape::Hemispherical:
    return " nose=hemispherical";
  case NoseGeometry::Shape::Conical:
    return " nose=conical length=" + exact(nose.length);
  case NoseGeometry::Shape::Ogival:
    return " nose=ogival crh=" + exact(nose.crh);
  }
  return "";
}

// A full cylinder keeps the text it had before quarters existed.
std::string geometry_signature(const GeometrySpec& g) {
  switch (g.kind) {
  case GeometrySpec::Kind::Box:
    return "box min=" + exact(g.box.min) + " max=" + exact(g.box.max);
  case GeometrySpec::Kind::Cylinder:
    return "cylinder base=" + exact(g.cylinder.base) + " axis=" + exact(g.cylinder.axis) +
           " radius=" + exact(g.cylinder.radius) +
           (g.cylinder.sector == Sector::Full ? "" : " sector=" + sector_name(g.cylinder.sector)) +
           nose_signature(g.cylinder.nose);
  case GeometrySpec::Kind::Ring:
    return "ring base=" + exact(g.ring.base) + " half_width=" + exact(g.ring.half_width) +
           " radius=" + exact(g.ring.radius) + " thickness=" + exact(g.ring.thickness) +
           " rim_element_size=" + exact(g.ring.rim_element_size) +
           " sector=" + sector_name(g.ring.sector);
  case GeometrySpec::Kind::File:
    return "file path=" + g.file.string() + " fnv1a64=" + content_hash(g.file);
  }
  return "unknown";
}

bool in_contact(const Case& c, const std::string& body) {
  return std::ranges::any_of(c.contacts, [&body](const ContactSpec& contact) {
    return contact.bodies[0] == body || contact.bodies[1] == body;
  });
}

// The discretisation keys of a body. An SPH body's particles carry its material's density. Its
// lattice is named also when centred (the default), so SPH models written before particle faces
// existed are stale and get remeshed. An FE body's h_factor sets its background particles' h
// only where it is in contact, so it is named only then (FE-only signatures keep their text).
std::string resolution_signature(const Case& c, const BodySpec& body) {
  if (body.method == Method::Fem)
    return "element_size=" + exact(body.element_size) +
           (in_contact(c, body.name) ? " h_factor=" + exact(body.h_factor) : "");
  const char* lattice = body.lattice == BodySpec::Lattice::Nodes ? "nodes" : "centred";
  return "spacing=" + exact(body.spacing) + " h_factor=" + exact(body.h_factor) +
         " lattice=" + lattice + " density=" + exact(c.material(body.material).density);
}

// The couplings, which decide the interface tags: one line per attachment and per contact pair
// (its model; its penalty, exponent and friction do not change the model), each pair's names in
// a fixed order, one per FE body whose every node the surface contact tags (its material
// erodes), and one per symmetry face of a body in contact; the lines sorted, since no order
// changes the tags. Empty without couplings.
std::string coupling_signature(const Case& c) {
  std::vector<std::string> lines;
  for (const AttachSpec& attach : c.attachments)
    lines.push_back("attach fem=" + attach.fem_body + " sph=" + attach.sph_body + "\n");
  for (const ContactSpec& contact : c.contacts) {
    const auto [a, b] = std::minmax(contact.bodies[0], contact.bodies[1]);
    const bool surface = contact.model == ContactModel::Surface;
    lines.push_back("contact " + a + " " + b + (surface ? " surface" : " kernel") + "\n");
    for (const std::string& name : contact.bodies)
      if (surface && mesher::exposes_inner_nodes(c, c.bodies[c.body_index(name)]))
        lines.push_back("exposed " + name + "\n");
  }
  // A contact body's symmetry faces carry no background particles.
  for (const BoundaryConditionSpec& bc : c.boundary_conditions)
    if (bc.type == BoundaryType::Symmetry && in_contact(c, bc.body))
      lines.push_back("symmetry " + bc.body + "/" + bc.face + "\n");
  std::ranges::sort(lines);
  std::string out;
  for (const std::string& line : lines)
    out += line;
  return out;
}

} // namespace

namespace mesher {

int divisions(double length, double element_size) {
  const double n = length / element_size;
  SPHFEM_CHECK(n < 1e6, "element_size ", element_size, " m gives ", n, " elements across ", length,
               " m");
  return std::max(1, static_cast<int>(std::lround(n)));
}

std::vector<Vec3> corner_points(int dim, int tag) {
  gmsh::vectorpair points;
  gmsh::model::getBoundary({{dim, tag}}, points, false, false, true);
  std::vector<Vec3> x;
  for (const auto& [point_dim, point] : points) {
    std::vector<double> c;
    gmsh::model::getValue(0, point, {}, c);
    x.emplace_back(c[0], c[1], c[2]);
  }
  return x;
}

std::vector<BoundarySurface> boundary_surfaces() {
  gmsh::vectorpair dim_tags;
  gmsh::model::getEntities(dim_tags, 2);
  std::vector<BoundarySurface> out;
  for (const auto& [dim, surface] : dim_tags) {
    std::vector<int> volumes, curves;
    gmsh::model::getAdjacencies(2, surface, volumes, curves);
    if (volumes.size() == 1)
      out.push_back({surface, corner_points(2, surface)});
  }
  return out;
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
  std::unique_ptr<GmshSession> session; // (std::optional draws a false -Wmaybe-uninitialized)
  for (std::size_t b = 0; b < c.bodies.size(); ++b) {
    // A geometry file's script may set any gmsh option: it gets a session of its own.
    if (reads_file(c.bodies[b]))
      session.reset();
    if (!session && needs_gmsh(c.bodies[b]))
      session = std::make_unique<GmshSession>();
    mesh_body(model, c, c.bodies[b], static_cast<int>(b));
    if (reads_file(c.bodies[b]))
      session.reset();
    model.body_names.push_back(c.bodies[b].name);
  }
  mesher::tag_interfaces(model, c);
  return model;
}

std::string mesh_signature(const Case& c) {
  std::ostringstream out;
  out << "sphfem-mesh 2\n"; // 2: cylinder cores meshed at the element size
  for (const BodySpec& body : c.bodies) {
    try {
      out << "body " << body.name << " method=" << method_name(body.method) << ' '
          << geometry_signature(body.geometry) << ' ' << resolution_signature(c, body) << '\n';
    } catch (const Error& e) {
      throw Error(detail::concat("mesh: body '", body.name, "': ", e.what()));
    }
  }
  out << coupling_signature(c);
  return out.str();
}

} // namespace sphfem
