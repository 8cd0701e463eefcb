#include "renderer/gl/shader.hpp"

#include <regex>

#include "terrain/error.hpp"

namespace renderer {

const std::string& shader_source(const std::string& name) {
  for (const auto& s : embedded_shaders())
    if (s.name == name) return s.source;
  throw terrain::Error("internal: no embedded shader named " + name);
}

std::string map_log_locations(const std::string& log, const std::vector<std::string>& files) {
  // Mesa: "0:12(3): error: ..."; NVIDIA: "1(12) : error ...". Source-string number N is
  // file N-1 (string 0 is the #version line).
  static const std::regex loc(R"((\d+):(\d+)\((\d+)\)|(\d+)\((\d+)\))");
  std::string out;
  auto begin = std::sregex_iterator(log.begin(), log.end(), loc);
  std::size_t last = 0;
  for (auto it = begin; it != std::sregex_iterator(); ++it) {
    const auto& m = *it;
    const int src = std::stoi(m[1].matched ? m[1].str() : m[4].str());
    const std::string line = m[1].matched ? m[2].str() : m[5].str();
    out += log.substr(last, std::size_t(m.position()) - last);
    if (src >= 1 && std::size_t(src) <= files.size())
      out += files[std::size_t(src) - 1] + ":" + line;
    else
      out += m.str();
    last = std::size_t(m.position() + m.length());
  }
  out += log.substr(last);
  return out;
}

namespace {

std::string one_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  for (auto& c : s)
    if (c == '\n') c = ' ';
  return s;
}

GLuint compile(const StageSource& st, const std::string& defines) {
  // String 0: the version, the C++/GLSL contract (renderer/gl/gl_contract.h) and the defines.
  std::vector<std::string> parts{"#version 450 core\n" + shader_source("gl_contract.h") + "\n" +
                                 defines};
  for (std::size_t i = 0; i < st.files.size(); ++i)
    parts.push_back("#line 1 " + std::to_string(i + 1) + "\n" + shader_source(st.files[i]) + "\n");
  std::vector<const char*> ptrs;
  for (const auto& p : parts) ptrs.push_back(p.c_str());
  const GLuint sh = glCreateShader(st.stage);
  glShaderSource(sh, GLsizei(ptrs.size()), ptrs.data(), nullptr);
  glCompileShader(sh);
  GLint ok = 0;
  glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetShaderiv(sh, GL_INFO_LOG_LENGTH, &len);
    std::string log(std::size_t(std::max(len, 1)), '\0');
    glGetShaderInfoLog(sh, len, nullptr, log.data());
    glDeleteShader(sh);
    throw terrain::Error("GLSL compile error: " +
                         one_line(map_log_locations(log.c_str(), st.files)));
  }
  return sh;
}

}  // namespace

GlObject build_program(const std::vector<StageSource>& stages,
                       const std::vector<std::string>& feedback, const std::string& defines) {
  GlObject prog(GlKind::Program);
  std::vector<GLuint> shaders;
  try {
    for (const auto& st : stages) shaders.push_back(compile(st, defines));
  } catch (...) {
    for (GLuint s : shaders) glDeleteShader(s);
    throw;
  }
  for (GLuint s : shaders) glAttachShader(prog.id(), s);
  if (!feedback.empty()) {
    std::vector<const char*> names;
    for (const auto& f : feedback) names.push_back(f.c_str());
    glTransformFeedbackVaryings(prog.id(), GLsizei(names.size()), names.data(),
                                GL_INTERLEAVED_ATTRIBS);
  }
  glLinkProgram(prog.id());
  for (GLuint s : shaders) {
    glDetachShader(prog.id(), s);
    glDeleteShader(s);
  }
  GLint ok = 0;
  glGetProgramiv(prog.id(), GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetProgramiv(prog.id(), GL_INFO_LOG_LENGTH, &len);
    std::string log(std::size_t(std::max(len, 1)), '\0');
    glGetProgramInfoLog(prog.id(), len, nullptr, log.data());
    std::string files;
    for (const auto& st : stages)
      for (const auto& f : st.files) files += (files.empty() ? "" : " ") + f;
    throw terrain::Error("GLSL link error (" + files + "): " + one_line(log.c_str()));
  }
  return prog;
}

}  // namespace renderer
