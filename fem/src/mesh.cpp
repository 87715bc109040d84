// Parametric ring/housing meshes: a structured (s, θ, z) block of hexahedra
// pushed through the exact chart of the cross-section (ring_chart.h).
#include "mesh_impl.h"
#include "ring_chart.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/tria.h>

#include <cmath>
#include <sstream>

namespace fretsim::fem
{
  std::string to_string(const BoundaryId id)
  {
    switch (id)
      {
        case BoundaryId::raceway: return "raceway";
        case BoundaryId::ring_lands: return "ring_lands";
        case BoundaryId::ring_outer: return "ring_outer";
        case BoundaryId::housing_bore: return "housing_bore";
        case BoundaryId::housing_outer: return "housing_outer";
        case BoundaryId::side_faces: return "side_faces";
        case BoundaryId::sector_start: return "sector_start";
        case BoundaryId::sector_end: return "sector_end";
      }
    return "boundary " + std::to_string(static_cast<unsigned int>(id));
  }

  std::string to_string(const MaterialId id)
  {
    switch (id)
      {
        case MaterialId::ring: return "ring";
        case MaterialId::housing: return "housing";
      }
    return "material " + std::to_string(static_cast<unsigned int>(id));
  }

  double RingGeometry::groove_half_width() const
  {
    if (!has_groove())
      return 0.0;
    const double centre = groove_bottom_radius - groove_radius;
    const double dr     = bore_radius - centre;
    return std::sqrt(groove_radius * groove_radius - dr * dr);
  }

  MeshError::MeshError(const std::string &file, const std::string &problem)
    : std::runtime_error(file + ": " + problem)
  {}

  MPI_Comm communicator_of(const Ranks ranks) { return ranks == Ranks::all ? MPI_COMM_WORLD : MPI_COMM_SELF; }

  Mesh::Mesh(std::unique_ptr<Impl> impl)
    : pimpl(std::move(impl))
  {}
  Mesh::~Mesh()                          = default;
  Mesh::Mesh(Mesh &&) noexcept            = default;
  Mesh &Mesh::operator=(Mesh &&) noexcept = default;

  namespace
  {
    /// One radial layer of a layered body: ring wall or housing wall.
    struct Layer
    {
      double       outer_radius;
      unsigned int cells;
      MaterialId   material;
      bool         fine_outside = true; ///< graded cells thinnest at the layer's outer side, else its inner
    };

    /// Vertex fractions 0 … 1 of `cells` radial cells whose sizes form a
    /// geometric progression from `grading` × the thinnest down to the thinnest
    /// (at the outer side, or at the inner with !fine_outside).
    std::vector<double> radial_fractions(unsigned int cells, double grading, bool fine_outside)
    {
      std::vector<double> sizes(cells, 1.0);
      if (cells > 1)
        for (unsigned int i = 0; i < cells; ++i)
          sizes[i] = std::pow(grading, (fine_outside ? double(cells - 1 - i) : double(i)) / (cells - 1));
      double total = 0.0;
      for (const double h : sizes)
        total += h;
      std::vector<double> fractions{0.0};
      double              sum = 0.0;
      for (unsigned int i = 0; i < cells; ++i)
        fractions.push_back(i + 1 == cells ? 1.0 : (sum += sizes[i]) / total);
      return fractions;
    }

    void check(const bool ok, const std::string &what)
    {
      if (!ok)
        throw std::invalid_argument("fem::Mesh: " + what);
    }

    void check_ring(const RingGeometry &ring)
    {
      check(ring.bore_radius > 0.0 && ring.outer_radius > ring.bore_radius && ring.width > 0.0,
            "ring needs 0 < bore radius < outer radius and width > 0");
      if (!ring.has_groove())
        return;
      check(ring.groove_bottom_radius > ring.bore_radius && ring.groove_bottom_radius < ring.outer_radius,
            "the groove bottom must lie between the bore (land) radius and the outer radius");
      check(ring.groove_bottom_radius - ring.groove_radius < ring.bore_radius,
            "the groove arc must reach the lands (groove radius > groove depth)");
      check(ring.groove_half_width() < 0.5 * ring.width, "the groove is wider than the ring");
    }

    /// Axial vertex positions: uniform, or lands | groove | lands with a vertex
    /// plane where the arc meets the lands (the profile's kink).
    std::vector<double> axial_nodes(const RingGeometry &profile, const MeshDivisions &d)
    {
      std::vector<double> z;
      const double        half = 0.5 * profile.width;
      auto                add  = [&z](double from, double to, unsigned int n) {
        for (unsigned int i = z.empty() ? 0 : 1; i <= n; ++i)
          z.push_back(from + (to - from) * i / n);
      };
      if (!profile.has_groove())
        add(-half, half, d.axial);
      else
        {
          const double zs = profile.groove_half_width();
          add(-half, -zs, d.axial_land);
          add(-zs, zs, d.axial);
          add(zs, half, d.axial_land);
        }
      return z;
    }

    std::unique_ptr<Mesh::Impl> layered_body(const RingGeometry &profile, const std::vector<Layer> &layers,
                                             const BoundaryId inner_id, const BoundaryId outer_id,
                                             const MeshDivisions &d, const Ranks ranks)
    {
      constexpr double two_pi = 2.0 * M_PI;
      const bool       full   = d.sector_angle >= two_pi * (1.0 - 1e-12);
      check(d.sector_angle > 0.0 && d.sector_angle <= two_pi * (1.0 + 1e-12), "sector angle must be in (0, 2π]");
      check(d.circumferential >= 3 && d.sector_angle / d.circumferential < 0.5 * M_PI,
            "need at least 3 cells around and cells spanning less than 90°");
      check(d.axial >= 1 && (!profile.has_groove() || d.axial_land >= 1), "need axial cells >= 1");
      check(d.radial_grading >= 1.0 && d.radial_grading <= 1e3, "radial grading must lie in [1, 1000]");

      std::vector<double> outer_radii;
      std::vector<double> s_nodes{0.0};
      for (unsigned int k = 0; k < layers.size(); ++k)
        {
          check(layers[k].cells >= 1, "need radial cells >= 1");
          outer_radii.push_back(layers[k].outer_radius);
          const std::vector<double> fractions =
            radial_fractions(layers[k].cells, d.radial_grading, layers[k].fine_outside);
          for (unsigned int i = 1; i <= layers[k].cells; ++i)
            s_nodes.push_back(k + fractions[i]);
        }
      const RingChart chart(profile, outer_radii);

      const std::vector<double> z_nodes = axial_nodes(profile, d);
      const unsigned int        n_s = s_nodes.size() - 1, n_t = d.circumferential, n_z = z_nodes.size() - 1;
      const unsigned int        n_t_vertices = full ? n_t : n_t + 1;

      std::vector<dealii::Point<3>> vertices;
      vertices.reserve((n_s + 1) * n_t_vertices * (n_z + 1));
      for (unsigned int k = 0; k <= n_z; ++k)
        for (unsigned int j = 0; j < n_t_vertices; ++j)
          for (unsigned int i = 0; i <= n_s; ++i)
            vertices.push_back(chart.push_forward({s_nodes[i], d.sector_angle * j / n_t, z_nodes[k]}));
      auto vertex = [&](unsigned int i, unsigned int j, unsigned int k) {
        return (k * n_t_vertices + (j % n_t_vertices)) * (n_s + 1) + i;
      };

      // Lexicographic vertex order in (s, θ, z), a right-handed frame
      // (e_r × e_θ = e_z), so every cell has a positive Jacobian.
      std::vector<dealii::CellData<3>> cells;
      cells.reserve(n_s * n_t * n_z);
      std::vector<unsigned int> layer_of_s(n_s);
      for (unsigned int i = 0; i < n_s; ++i)
        layer_of_s[i] = static_cast<unsigned int>(std::floor(0.5 * (s_nodes[i] + s_nodes[i + 1])));
      for (unsigned int k = 0; k < n_z; ++k)
        for (unsigned int j = 0; j < n_t; ++j)
          for (unsigned int i = 0; i < n_s; ++i)
            {
              dealii::CellData<3> cell;
              unsigned int        v = 0;
              for (unsigned int c = 0; c < 2; ++c)
                for (unsigned int b = 0; b < 2; ++b)
                  for (unsigned int a = 0; a < 2; ++a)
                    cell.vertices[v++] = vertex(i + a, j + b, k + c);
              cell.material_id = static_cast<unsigned int>(layers[layer_of_s[i]].material);
              cell.manifold_id = 0;
              cells.push_back(cell);
            }

      auto impl = std::make_unique<Mesh::Impl>(communicator_of(ranks));
      auto &tria = impl->triangulation;
      tria.create_triangulation(vertices, cells, dealii::SubCellData());

      // Coarse cells keep the order in which they were given.
      const double zs        = profile.groove_half_width();
      unsigned int cell_no   = 0;
      for (auto cell = tria.begin(0); cell != tria.end(0); ++cell, ++cell_no)
        {
          const unsigned int i = cell_no % n_s, j = (cell_no / n_s) % n_t, k = cell_no / (n_s * n_t);
          if (i == 0)
            {
              const double zc      = 0.5 * (z_nodes[k] + z_nodes[k + 1]);
              const bool   in_land = profile.has_groove() && std::abs(zc) > zs;
              cell->face(0)->set_boundary_id(static_cast<unsigned int>(in_land ? BoundaryId::ring_lands : inner_id));
            }
          if (i == n_s - 1)
            cell->face(1)->set_boundary_id(static_cast<unsigned int>(outer_id));
          if (!full && j == 0)
            cell->face(2)->set_boundary_id(static_cast<unsigned int>(BoundaryId::sector_start));
          if (!full && j == n_t - 1)
            cell->face(3)->set_boundary_id(static_cast<unsigned int>(BoundaryId::sector_end));
          if (k == 0)
            cell->face(4)->set_boundary_id(static_cast<unsigned int>(BoundaryId::side_faces));
          if (k == n_z - 1)
            cell->face(5)->set_boundary_id(static_cast<unsigned int>(BoundaryId::side_faces));
        }
      tria.set_all_manifold_ids(0);
      tria.set_manifold(0, chart);
      return impl;
    }

    std::string describe(const RingGeometry &ring, const MeshDivisions &d)
    {
      std::ostringstream s;
      s << "ring bore " << ring.bore_radius << " m, outer " << ring.outer_radius << " m, width " << ring.width
        << " m";
      if (ring.has_groove())
        s << ", groove radius " << ring.groove_radius << " m, groove bottom " << ring.groove_bottom_radius << " m";
      s << "; cells " << d.circumferential << " around " << d.sector_angle << " rad, " << d.radial_ring
        << " radial, " << d.axial << " axial";
      if (d.radial_grading != 1.0)
        s << ", radial grading " << d.radial_grading;
      if (ring.has_groove())
        s << " (+" << d.axial_land << " per land)";
      return s.str();
    }
  } // namespace

  Mesh Mesh::ring(const RingGeometry &ring, const MeshDivisions &d, const Ranks ranks)
  {
    check_ring(ring);
    auto impl = layered_body(ring, {{ring.outer_radius, d.radial_ring, MaterialId::ring}}, BoundaryId::raceway,
                             BoundaryId::ring_outer, d, ranks);
    impl->description = "parametric " + describe(ring, d);
    return Mesh(std::move(impl));
  }

  Mesh Mesh::housing(const HousingGeometry &housing, const MeshDivisions &d, const Ranks ranks)
  {
    RingGeometry profile;
    profile.bore_radius  = housing.bore_radius;
    profile.outer_radius = housing.outer_radius;
    profile.width        = housing.width;
    check_ring(profile);
    auto impl = layered_body(profile, {{housing.outer_radius, d.radial_housing, MaterialId::housing, false}},
                             BoundaryId::housing_bore, BoundaryId::housing_outer, d, ranks);
    std::ostringstream s;
    s << "parametric housing bore " << housing.bore_radius << " m, outer " << housing.outer_radius
      << " m, width " << housing.width << " m; cells " << d.circumferential << " around, " << d.radial_housing
      << " radial, " << d.axial << " axial";
    impl->description = s.str();
    return Mesh(std::move(impl));
  }

  Mesh Mesh::ring_in_housing(const RingGeometry &ring, const HousingGeometry &housing, const MeshDivisions &d,
                             const Ranks ranks)
  {
    check_ring(ring);
    check(std::abs(housing.bore_radius - ring.outer_radius) <= 1e-12 * ring.outer_radius,
          "bonded ring and housing need housing bore radius = ring outer radius (model a fit with an eigenstrain)");
    check(std::abs(housing.width - ring.width) <= 1e-12 * ring.width, "housing and ring need the same width");
    check(housing.outer_radius > housing.bore_radius, "housing needs outer radius > bore radius");
    auto impl = layered_body(ring,
                             {{ring.outer_radius, d.radial_ring, MaterialId::ring},
                              {housing.outer_radius, d.radial_housing, MaterialId::housing, false}},
                             BoundaryId::raceway, BoundaryId::housing_outer, d, ranks);
    std::ostringstream s;
    s << "parametric " << describe(ring, d) << "; bonded in housing of outer radius " << housing.outer_radius
      << " m with " << d.radial_housing << " radial cells";
    impl->description = s.str();
    return Mesh(std::move(impl));
  }

  void Mesh::refine_globally(const unsigned int times) { pimpl->triangulation.refine_global(times); }

  unsigned int Mesh::n_ranks() const { return dealii::Utilities::MPI::n_mpi_processes(pimpl->communicator()); }
  unsigned int Mesh::rank() const { return dealii::Utilities::MPI::this_mpi_process(pimpl->communicator()); }

  MeshSummary Mesh::summary(const unsigned int mapping_degree) const
  {
    const auto &tria = pimpl->triangulation;
    const MPI_Comm comm = pimpl->communicator();
    const dealii::MappingQ<3>  mapping(mapping_degree);
    const dealii::FE_Q<3>      fe(1);
    const dealii::QGauss<3>    quadrature(4);
    const dealii::QGauss<2>    face_quadrature(4);
    dealii::FEValues<3>        fe_values(mapping, fe, quadrature, dealii::update_JxW_values);
    dealii::FEFaceValues<3>    fe_face_values(mapping, fe, face_quadrature, dealii::update_JxW_values);

    std::map<unsigned int, double> face_count, area, cell_count, volume;
    for (const auto &cell : tria.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        fe_values.reinit(cell);
        double v = 0.0;
        for (const double jxw : fe_values.get_JxW_values())
          v += jxw;
        volume[cell->material_id()] += v;
        cell_count[cell->material_id()] += 1.0;
        for (unsigned int f = 0; f < cell->n_faces(); ++f)
          if (cell->face(f)->at_boundary())
            {
              fe_face_values.reinit(cell, f);
              double a = 0.0;
              for (const double jxw : fe_face_values.get_JxW_values())
                a += jxw;
              area[cell->face(f)->boundary_id()] += a;
              face_count[cell->face(f)->boundary_id()] += 1.0;
            }
      }

    // Every rank contributes the ids it has seen; sum over ranks per id.
    auto reduce = [comm](const std::map<unsigned int, double> &local) {
      std::map<unsigned int, double> all;
      for (const auto &part : dealii::Utilities::MPI::all_gather(comm, local))
        for (const auto &[id, value] : part)
          all[id] += value;
      return all;
    };

    MeshSummary s;
    s.n_cells     = tria.n_global_active_cells();
    s.n_ranks     = n_ranks();
    s.description = pimpl->description;
    for (const auto &[id, n] : reduce(face_count))
      s.boundary_faces[id] = static_cast<unsigned long>(std::lround(n));
    s.boundary_area = reduce(area);
    for (const auto &[id, n] : reduce(cell_count))
      s.material_cells[id] = static_cast<unsigned long>(std::lround(n));
    s.material_volume = reduce(volume);
    for (const auto &[id, v] : s.material_volume)
      s.volume += v;
    return s;
  }

  unsigned long Mesh::n_dofs(const unsigned int degree) const
  {
    if (degree != 1 && degree != 2)
      throw std::invalid_argument("fem::Mesh::n_dofs: element degree must be 1 or 2, not " + std::to_string(degree));
    const dealii::FESystem<3> fe(dealii::FE_Q<3>(degree), 3);
    dealii::DoFHandler<3>     dof_handler(pimpl->triangulation);
    dof_handler.distribute_dofs(fe);
    return dof_handler.n_dofs();
  }
} // namespace fretsim::fem
