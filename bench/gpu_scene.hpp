#pragma once
// A scene for the GPU benchmark (gpu_flight.cpp) as one raw file: the mesh (grid, georeference,
// positions, normals, Voronoi weights) and the creases built from the drainage database, so
// that the benchmark can be carried to a GPU machine without the libraries that read PLY and
// .dv files. Written by gpu-flight-scene and read by gpu-flight, both built from one tree (the
// file is this tree's structures byte for byte; the header names the format's version).
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include "renderer/core/crease.hpp"
#include "renderer/core/options.hpp"
#include "terrain/grid_mesh.hpp"

namespace gpu_scene {

inline constexpr char kMagic[8] = {'T', 'R', 'S', 'C', 'E', 'N', 'E', '1'};

struct Scene {
  terrain::GridMesh mesh;
  std::optional<renderer::CreaseGeometry> creases;
};

class Writer {
 public:
  explicit Writer(const std::string& path)
      : out_(path, std::ios::binary | std::ios::trunc), path_(path) {
    if (!out_) throw std::runtime_error("cannot write '" + path + "'");
  }
  template <class T>
  void pod(const T& v) {
    out_.write(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <class V>
  void array(const V& v) {
    pod(std::uint64_t(v.size()));
    out_.write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size() * sizeof(v[0])));
  }
  void finish() {
    out_.flush();
    if (!out_) throw std::runtime_error("cannot write '" + path_ + "' (disk full?)");
  }

 private:
  std::ofstream out_;
  std::string path_;
};

class Reader {
 public:
  explicit Reader(const std::string& path) : in_(path, std::ios::binary), path_(path) {
    if (!in_) throw std::runtime_error("cannot read '" + path + "'");
  }
  template <class T>
  void pod(T& v) {
    in_.read(reinterpret_cast<char*>(&v), sizeof v);
    if (!in_) throw std::runtime_error("'" + path_ + "' is truncated");
  }
  template <class V>
  void array(V& v) {
    std::uint64_t n = 0;
    pod(n);
    if (n > (std::uint64_t(1) << 34) / sizeof(v[0]))
      throw std::runtime_error("'" + path_ + "' is not a scene file");
    v.resize(n);
    in_.read(reinterpret_cast<char*>(v.data()), std::streamsize(n * sizeof(v[0])));
    if (!in_) throw std::runtime_error("'" + path_ + "' is truncated");
  }

 private:
  std::ifstream in_;
  std::string path_;
};

inline void write_to(const std::string& path, const terrain::GridMesh& m,
                     const renderer::CreaseGeometry* c) {
  Writer w(path);
  w.pod(kMagic);
  w.pod(std::uint64_t(m.topo.rows)), w.pod(std::uint64_t(m.topo.cols));
  w.pod(m.geo.epsg), w.pod(m.geo.origin_x), w.pod(m.geo.origin_y), w.pod(m.geo.origin_z),
      w.pod(m.geo.dx), w.pod(m.geo.dy);
  w.array(m.geo.crs_wkt);
  w.array(m.positions), w.array(m.normals);
  w.array(m.voronoi.corner_areas), w.array(m.voronoi.vertex_areas), w.array(m.voronoi.tangents);
  w.pod(std::uint8_t(c ? 1 : 0));
  if (c) {
    w.array(c->positions), w.array(c->source), w.array(c->normals), w.array(c->flow),
        w.array(c->share);
    w.array(c->segments);
    w.pod(c->median_surface_offset);
  }
  w.finish();
}

// Written to a temporary file of this process beside `path`, renamed onto it when whole.
inline void write(const std::string& path, const terrain::GridMesh& m,
                  const renderer::CreaseGeometry* c) {
  const std::string temp = path + ".partial." + std::to_string(::getpid());
  try {
    write_to(temp, m, c);
    std::filesystem::rename(temp, path);
  } catch (const std::exception& e) {
    std::error_code ec;
    std::filesystem::remove(temp, ec);
    throw std::runtime_error("cannot write '" + path + "' (" + e.what() + ")");
  }
}

inline Scene read(const std::string& path) {
  Reader r(path);
  char magic[8];
  r.pod(magic);
  if (std::memcmp(magic, kMagic, 8) != 0)
    throw std::runtime_error("'" + path +
                             "' is not a scene file of this build (make it with gpu-flight-scene)");
  Scene s;
  terrain::GridMesh& m = s.mesh;
  std::uint64_t rows = 0, cols = 0;
  r.pod(rows), r.pod(cols);
  m.topo.rows = std::size_t(rows), m.topo.cols = std::size_t(cols);
  r.pod(m.geo.epsg), r.pod(m.geo.origin_x), r.pod(m.geo.origin_y), r.pod(m.geo.origin_z),
      r.pod(m.geo.dx), r.pod(m.geo.dy);
  r.array(m.geo.crs_wkt);
  r.array(m.positions), r.array(m.normals);
  r.array(m.voronoi.corner_areas), r.array(m.voronoi.vertex_areas), r.array(m.voronoi.tangents);
  if (m.positions.size() != m.topo.n_vertices() || m.normals.size() != m.positions.size())
    throw std::runtime_error("'" + path + "': the mesh's arrays do not match its grid");
  std::uint8_t has = 0;
  r.pod(has);
  if (has) {
    renderer::CreaseGeometry& c = s.creases.emplace();
    r.array(c.positions), r.array(c.source), r.array(c.normals), r.array(c.flow), r.array(c.share);
    r.array(c.segments);
    r.pod(c.median_surface_offset);
  }
  return s;
}

// terrain-render's options after the positional arguments: "--name value", "--name=value",
// or a flag alone ("--aliased"); returns the positional arguments.
inline std::vector<std::string> parse_args(int argc, char** argv, renderer::RenderSettings& s) {
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a.rfind("--", 0) != 0) {
      positional.push_back(a);
      continue;
    }
    std::string name = a.substr(2), value;
    const auto eq = name.find('=');
    if (eq != std::string::npos) value = name.substr(eq + 1), name = name.substr(0, eq);
    const renderer::OptionSpec* o = renderer::find_option(name);
    if (!o)
      throw std::runtime_error("unknown option --" + name +
                               " (terrain-render's options are taken)");
    if (eq == std::string::npos) {
      if (o->type == renderer::OptionType::Bool)
        value = "true";
      else if (i + 1 < argc)
        value = argv[++i];
      else
        throw std::runtime_error("--" + name + " needs a value");
    }
    try {
      renderer::set_option(s, *o, value);
    } catch (const std::exception& e) {
      throw std::runtime_error("--" + name + ": " + e.what());
    }
  }
  renderer::validate(s);
  return positional;
}

}  // namespace gpu_scene
