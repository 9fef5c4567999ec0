#pragma once
// Numbers in messages and reports.

#include <iomanip>
#include <sstream>
#include <string>

namespace perideal
{
  /// @p v with @p digits significant digits.
  inline std::string
  sci(const double v, const unsigned int digits = 4)
  {
    std::ostringstream o;
    o << std::setprecision(digits) << v;
    return o.str();
  }

  inline std::string
  mib(const double bytes)
  {
    std::ostringstream o;
    o << std::fixed << std::setprecision(1) << bytes / 1048576.0 << " MiB";
    return o.str();
  }

  inline std::string
  format_seconds(const double s)
  {
    std::ostringstream o;
    if (s < 60)
      o << std::fixed << std::setprecision(1) << s << " s";
    else if (s < 3600)
      o << int(s) / 60 << " min " << int(s) % 60 << " s";
    else
      o << int(s) / 3600 << " h " << (int(s) % 3600) / 60 << " min";
    return o.str();
  }
} // namespace perideal
