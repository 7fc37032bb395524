#include "solver/material/material.hpp"

#include "solver/core/error.hpp"
#include "solver/io/case.hpp"

namespace sphfem {

Material Material::from(const MaterialSpec& spec) {
  Material m;
  m.elastic = ElasticConstants::from(spec);
  m.eos = spec.eos;
  m.erosion = spec.erosion;
  if (spec.model == "elastic")
    return m;
  if (spec.model == "johnson_cook") {
    SPHFEM_CHECK(spec.johnson_cook.has_value(), "material ", spec.name,
                 ": model johnson_cook needs its constants");
    m.strength = spec.johnson_cook;
    m.damage = spec.damage;
    m.heating = spec.heating;
    return m;
  }
  throw Error("material " + spec.name + ": unknown model '" + spec.model +
              "' (expected one of: elastic, johnson_cook)");
}

} // namespace sphfem
