// perideal_check fields: checks the field files of a pd_app run (one output
// step: its .pvtu and the .vtu pieces it lists) against values given per
// field:
//
//   perideal_check fields PVTU --field NAME TOL V1 ... VN [--field ...]
//
// - the .pvtu declares NAME with N components (1 scalar, 3 vector, 9 tensor,
//   row-major), and so does every piece;
// - at every point of every piece, |component k - Vk| <= TOL for every k.
// deal.II writes the values as Float32 (about 7 significant digits), so TOL
// cannot be below about 1e-7 |V|. The pieces are read as deal.II 9.4 writes
// them: base64, each array one zlib block after its 4-word header
// (vtkZLibDataCompressor), or plain base64 with a 1-word size header, or ASCII.
// Prints per field the number of values read (over all pieces: the same for
// any number of ranks) and the largest difference, with PASS/FAIL. Serial; no MPI.

#include "check.h"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
  std::string
  read_text(const std::string &file)
  {
    std::ifstream in(file, std::ios::binary);
    if (!in)
      throw std::runtime_error("cannot open " + file);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }

  /// The value of attribute @p name in the XML tag @p tag, or "".
  std::string
  attribute(const std::string &tag, const std::string &name)
  {
    const std::string key = " " + name + "=\"";
    const auto        at  = tag.find(key);
    if (at == std::string::npos)
      return "";
    const auto begin = at + key.size();
    return tag.substr(begin, tag.find('"', begin) - begin);
  }

  std::vector<unsigned char>
  decode_base64(const std::string &text)
  {
    static const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::vector<unsigned char> out;
    unsigned int               buffer = 0, bits = 0;
    for (const char c : text)
      {
        if (c == '=' || std::isspace(static_cast<unsigned char>(c)))
          continue;
        const auto v = alphabet.find(c);
        if (v == std::string::npos)
          throw std::runtime_error("not base64: '" + std::string(1, c) + "'");
        buffer = (buffer << 6) | v;
        bits += 6;
        if (bits >= 8)
          {
            bits -= 8;
            out.push_back((buffer >> bits) & 0xff);
          }
      }
    return out;
  }

  /// Array @p name of the PointData of VTU text @p vtu: its values and components.
  std::vector<double>
  read_array(const std::string &vtu, const std::string &name, const bool compressed, unsigned int &components)
  {
    const auto data = vtu.find("<PointData");
    if (data == std::string::npos)
      throw std::runtime_error("no PointData");
    const auto at = vtu.find("Name=\"" + name + "\"", data);
    if (at == std::string::npos)
      throw std::runtime_error("no array '" + name + "'");
    const auto        open  = vtu.rfind('<', at);
    const auto        close = vtu.find('>', at);
    const std::string tag   = vtu.substr(open, close - open);
    const std::string type  = attribute(tag, "type");
    const std::string n     = attribute(tag, "NumberOfComponents");
    components              = n.empty() ? 1 : std::stoi(n);
    const auto        end   = vtu.find("</DataArray>", close);
    const std::string body  = vtu.substr(close + 1, end - close - 1);

    std::vector<double> values;
    // A rank that holds no point writes an empty piece: its arrays are empty.
    if (body.find_first_not_of(" \t\r\n") == std::string::npos)
      return values;
    if (attribute(tag, "format") == "ascii")
      {
        std::istringstream s(body);
        for (double v; s >> v;)
          values.push_back(v);
        return values;
      }
    std::vector<unsigned char> bytes;
    if (compressed)
      {
        // 4 uint32 (blocks = 1, block size, last block size, compressed
        // size), base64 on their own (24 characters), then the block.
        std::string text;
        for (const char c : body)
          if (!std::isspace(static_cast<unsigned char>(c)))
            text += c;
        const auto header = decode_base64(text.substr(0, 24));
        uint32_t   h[4];
        std::memcpy(h, header.data(), sizeof(h));
        if (h[0] != 1)
          throw std::runtime_error("array '" + name + "': " + std::to_string(h[0]) + " zlib blocks, expected 1");
        const auto block = decode_base64(text.substr(24));
        bytes.resize(h[1]);
        uLongf size = h[1];
        if (uncompress(bytes.data(), &size, block.data(), block.size()) != Z_OK || size != h[1])
          throw std::runtime_error("array '" + name + "': zlib cannot inflate it");
      }
    else
      {
        const auto raw = decode_base64(body);
        uint32_t   size;
        std::memcpy(&size, raw.data(), sizeof(size));
        bytes.assign(raw.begin() + sizeof(size), raw.begin() + sizeof(size) + size);
      }
    if (type == "Float32")
      for (std::size_t k = 0; k + 4 <= bytes.size(); k += 4)
        {
          float v;
          std::memcpy(&v, &bytes[k], 4);
          values.push_back(v);
        }
    else if (type == "Float64")
      for (std::size_t k = 0; k + 8 <= bytes.size(); k += 8)
        {
          double v;
          std::memcpy(&v, &bytes[k], 8);
          values.push_back(v);
        }
    else
      throw std::runtime_error("array '" + name + "' of type " + type);
    return values;
  }

  struct Field
  {
    std::string         name;
    double              tol;
    std::vector<double> expected;
  };
} // namespace

int
check_fields(int argc, char *argv[])
{
  try
    {
      if (argc < 2)
        throw std::runtime_error("usage: perideal_check fields PVTU --field NAME TOL V1 ... VN ...");
      const std::string  pvtu = argv[1];
      std::vector<Field> fields;
      for (int a = 2; a < argc; ++a)
        {
          const std::string arg = argv[a];
          if (arg != "--field")
            throw std::runtime_error("unknown argument " + arg);
          Field f;
          f.name = check_common::next_argument(argc, argv, a, arg);
          f.tol  = std::atof(check_common::next_argument(argc, argv, a, arg).c_str());
          while (a + 1 < argc && std::string(argv[a + 1]) != "--field")
            f.expected.push_back(std::atof(argv[++a]));
          if (f.expected.size() != 1 && f.expected.size() != 3 && f.expected.size() != 9)
            throw std::runtime_error("--field " + f.name + ": give 1, 3 or 9 values");
          fields.push_back(f);
        }

      // The pieces, in the .pvtu's directory.
      const std::string        record = read_text(pvtu);
      const std::string        dir    = pvtu.find('/') == std::string::npos ? "" : pvtu.substr(0, pvtu.rfind('/') + 1);
      std::vector<std::string> pieces;
      for (auto at = record.find("<Piece "); at != std::string::npos; at = record.find("<Piece ", at + 1))
        pieces.push_back(dir + attribute(record.substr(at, record.find('>', at) - at), "Source"));
      if (pieces.empty())
        throw std::runtime_error("no pieces in " + pvtu);

      for (const auto &f : fields)
        {
          const unsigned int n = f.expected.size();
          // The .pvtu's declaration.
          const auto at = record.find("Name=\"" + f.name + "\"");
          if (at == std::string::npos)
            throw std::runtime_error(pvtu + " has no array '" + f.name + "'");
          const auto        open = record.rfind('<', at);
          const std::string tag  = record.substr(open, record.find('>', at) - open);
          const std::string c    = attribute(tag, "NumberOfComponents");
          const unsigned int declared = c.empty() ? 1 : std::stoi(c);

          std::size_t  values = 0;
          double       worst  = 0;
          unsigned int found  = n;
          for (const auto &piece : pieces)
            {
              const std::string vtu        = read_text(piece);
              const bool        compressed = vtu.find("vtkZLibDataCompressor") != std::string::npos;
              unsigned int      components = 0;
              const auto        data       = read_array(vtu, f.name, compressed, components);
              if (components != n)
                found = components;
              for (std::size_t k = 0; k < data.size(); ++k)
                worst = std::max(worst, std::abs(data[k] - f.expected[k % components]));
              values += data.size() / components;
            }
          std::cout << f.name << ": " << values << " values (8 per point)\n";
          check_common::check("  components in the .pvtu", declared, declared == n, "== " + std::to_string(n), 6);
          check_common::check("  components in the pieces", found, found == n, "== " + std::to_string(n), 6);
          check_common::check("  max |value - expected|", worst, values > 0 && worst <= f.tol,
                              "<= " + check_common::str(f.tol), 2);
        }
    }
  catch (const std::exception &e)
    {
      std::cout << "Error: " << e.what() << std::endl;
      return 2;
    }
  return check_common::finish();
}
