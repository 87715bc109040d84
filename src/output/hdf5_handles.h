#pragma once
// The HDF5 C API's error reporting and identifiers for the output files'
// sources (never a public header): every call checked, failures thrown as
// std::runtime_error naming the file, the object and HDF5's own reason.
#include <hdf5.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace fretsim::output::hdf5
{
  /// While alive, HDF5 prints nothing by itself (errors are reported through
  /// exceptions instead); the previous handler comes back afterwards so other
  /// HDF5 users in the process keep their setting.
  class QuietErrors
  {
  public:
    QuietErrors()
    {
      if (H5Eget_auto2(H5E_DEFAULT, &function, &data) < 0)
        function = nullptr, data = nullptr;
      H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    }
    ~QuietErrors() { H5Eset_auto2(H5E_DEFAULT, function, data); }
    QuietErrors(const QuietErrors &)            = delete;
    QuietErrors &operator=(const QuietErrors &) = delete;

  private:
    H5E_auto2_t function = nullptr;
    void       *data     = nullptr;
  };

  inline herr_t collect_error(unsigned position, const H5E_error2_t *error, void *client)
  {
    // The innermost error says what went wrong; the rest is HDF5's call path.
    auto &text = *static_cast<std::string *>(client);
    if (position == 0 && error->desc)
      text = error->desc;
    return 0;
  }

  /// The current HDF5 error in one short line: the system's reason (e.g.
  /// "No space left on device") where HDF5 quotes one, else the innermost
  /// error's description.
  inline std::string hdf5_reason()
  {
    std::string text;
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, collect_error, &text);
    const auto quoted = text.find("error message = '");
    if (quoted != std::string::npos)
      {
        const auto start = quoted + 17;
        return text.substr(start, text.find('\'', start) - start);
      }
    std::replace(text.begin(), text.end(), '\n', ' ');
    return text;
  }

  [[noreturn]] inline void fail(const std::string &file, const std::string &object, const std::string &what)
  {
    std::string message = "results file '" + file + "'";
    if (!object.empty())
      message += ", " + object;
    message += ": " + what;
    const std::string reason = hdf5_reason();
    if (!reason.empty())
      message += " (HDF5: " + reason + ")";
    H5Eclear2(H5E_DEFAULT);
    throw std::runtime_error(message);
  }

  /// Throws unless an HDF5 return value (hid_t, herr_t, htri_t) is non-negative.
  template <typename T>
  T check(T value, const std::string &file, const std::string &object, const char *what)
  {
    if (value < 0)
      fail(file, object, what);
    return value;
  }

  /// Owns one HDF5 identifier and closes it with the matching H5?close.
  class Handle
  {
  public:
    using Closer = herr_t (*)(hid_t);
    Handle() = default;
    Handle(hid_t id, Closer closer) : id(id), closer(closer) {}
    Handle(Handle &&other) noexcept : id(other.id), closer(other.closer) { other.id = H5I_INVALID_HID; }
    Handle &operator=(Handle &&other) noexcept
    {
      if (this != &other)
        {
          reset();
          id = other.id, closer = other.closer;
          other.id = H5I_INVALID_HID;
        }
      return *this;
    }
    ~Handle() { reset(); }
    Handle(const Handle &)            = delete;
    Handle &operator=(const Handle &) = delete;

    hid_t get() const { return id; }
    bool  valid() const { return id >= 0; }
    /// Closes now; returns false if HDF5 reports a failure.
    bool reset()
    {
      bool ok = true;
      if (id >= 0 && closer)
        ok = closer(id) >= 0;
      id = H5I_INVALID_HID;
      return ok;
    }

  private:
    hid_t  id     = H5I_INVALID_HID;
    Closer closer = nullptr;
  };

  inline Handle make(hid_t id, Handle::Closer closer, const std::string &file, const std::string &object, const char *what)
  {
    return Handle(check(id, file, object, what), closer);
  }
} // namespace fretsim::output::hdf5
