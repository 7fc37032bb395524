// StateArchive: the state of a run, field by field, for checkpoints (OUT/checkpoint.h5). Each
// owner of state has one persist(StateArchive&) that names its fields; the same function writes
// them and reads them back, so a field cannot be written and forgotten on reading. Arrays are
// stored as their bytes, exactly (a restart continues bit for bit), with the element size, so a
// file of another build's layout is refused rather than misread. Names are paths
// ("particles/x_p"). The HDF5 implementation is in checkpoint.cpp.
#pragma once

#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

namespace sphfem {

class StateArchive {
public:
  virtual ~StateArchive() = default;
  virtual bool reading() const = 0;

  // Plain data only: numbers, Eigen fixed-size vectors and matrices, std::array of them,
  // structs of such (MaterialPoint).
  template <class T> void array(const std::string& name, std::vector<T>& v) {
    static_assert(std::is_trivially_destructible_v<T> && !std::is_pointer_v<T>,
                  "a checkpoint stores plain data");
    if (reading())
      v.resize(stored_count(name, sizeof(T)));
    bytes(name, v.data(), v.size(), sizeof(T));
  }
  template <class T> void value(const std::string& name, T& x) {
    static_assert(std::is_trivially_destructible_v<T> && !std::is_pointer_v<T>,
                  "a checkpoint stores plain data");
    if (reading())
      expect_count(name, sizeof(T), 1);
    bytes(name, &x, 1, sizeof(T));
  }
  void text(const std::string& name, std::string& s);

protected:
  // Reading: the number of elements stored under `name`; an Error if it is absent or its
  // elements are not `element` bytes long.
  virtual std::size_t stored_count(const std::string& name, std::size_t element) = 0;
  // Writing: stores count × element bytes from `data`; reading: fills them.
  virtual void bytes(const std::string& name, void* data, std::size_t count,
                     std::size_t element) = 0;

private:
  void expect_count(const std::string& name, std::size_t element, std::size_t count);
};

// Writes nothing: a rank of a distributed run that takes part in the gathers of a checkpoint
// rank 0 writes (Simulation::persist).
class DiscardingArchive final : public StateArchive {
public:
  bool reading() const override { return false; }

protected:
  std::size_t stored_count(const std::string&, std::size_t) override { return 0; }
  void bytes(const std::string&, void*, std::size_t, std::size_t) override {}
};

} // namespace sphfem
