// Hdf5Errors: while alive, HDF5 prints nothing on failure and the innermost description of its
// first failure (e.g. "truncated file: eof = …") is kept for our one-line message. Used by the
// readers of model.h5 and checkpoint.h5.
#pragma once

#include <H5Cpp.h>

#include <string>

namespace sphfem {

class Hdf5Errors {
public:
  Hdf5Errors() {
    H5Eget_auto2(H5E_DEFAULT, &saved_, &saved_data_);
    H5Eset_auto2(H5E_DEFAULT, &Hdf5Errors::record, &first_);
  }
  ~Hdf5Errors() { H5Eset_auto2(H5E_DEFAULT, saved_, saved_data_); }
  Hdf5Errors(const Hdf5Errors&) = delete;
  Hdf5Errors& operator=(const Hdf5Errors&) = delete;

  std::string describe(const H5::Exception& e) const {
    return first_.empty() ? e.getFuncName() + ": " + e.getDetailMsg() : first_;
  }

private:
  static herr_t record(hid_t stack, void* first) {
    if (static_cast<std::string*>(first)->empty())
      H5Ewalk2(stack, H5E_WALK_UPWARD, &innermost, first);
    return 0;
  }
  static herr_t innermost(unsigned n, const H5E_error2_t* error, void* first) {
    if (n == 0 && error->desc != nullptr)
      *static_cast<std::string*>(first) = error->desc;
    return 0;
  }

  H5E_auto2_t saved_ = nullptr;
  void* saved_data_ = nullptr;
  std::string first_;
};

} // namespace sphfem
