#pragma once
// Fields of a loaded elastic body for visualisation: displacement and von Mises stress per body
// and mesh position (deal.II DataOut, one .vtu per rank and a .pvtu record), and the contact
// pressure of the contact grid as a point data set (.vtu) in the body's frame.
//
// Units follow the body (hertzgear's FE bodies are in mm and MPa: displacement in mm, stress in
// MPa). In 2D (plane strain) the von Mises stress includes sigma_zz = lambda tr(eps).
#include "fem/elastic_body.h"

#include <array>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace hertzgear::fem
{
  // Writes DIR/NAME_CCCC.R.vtu on every rank R and DIR/NAME_CCCC.pvtu (counter CCCC) and returns
  // the .pvtu file name (no directory). Collective over the body's communicator.
  template <int dim>
  std::string write_body_fields(const ElasticBody<dim> &                             body,
                                const typename ElasticBody<dim>::VectorType &        displacement,
                                const std::filesystem::path &                        directory,
                                const std::string &                                  name,
                                unsigned int                                         counter);

  // A point data set: one VTK vertex per point with the given scalar point data (ASCII .vtu,
  // serial: call it on one rank).
  void write_point_cloud_vtu(const std::filesystem::path &                    file,
                             const std::vector<std::array<double, 3>> &       points,
                             const std::vector<std::pair<std::string, std::vector<double>>> &data);

  // A ParaView .pvd collection: (time, file) per entry.
  void write_pvd(const std::filesystem::path &                     file,
                 const std::vector<std::pair<double, std::string>> &entries);
} // namespace hertzgear::fem
