#pragma once
// An Exodus II mesh file (Peridigm's usual discretization) as written: its
// nodes, element blocks, node sets and side sets, read through the Exodus II
// library. A file decomposed for N processes (FILE.N.0, ..., FILE.N.N-1, as
// Sandia's decomp writes them) is read whole: its pieces are joined by their
// global node and element numbers.

#include <perideal/base/input.h>

#include <deal.II/base/point.h>

#include <string>
#include <vector>

namespace perideal
{
  struct ExodusMesh
  {
    /// The nodes' coordinates, node n at index n - 1: n is the node's place
    /// in a whole file, its global number (the node map) in a decomposition.
    std::vector<dealii::Point<dim>> nodes;

    struct Block
    {
      long        id;
      std::string name; // "block_<id>" if the file names none, as Peridigm does
      std::string type; // the file's element type in capitals: SPHERE, HEX8, TETRA, ...
      unsigned int nodes_per_element = 0, n_attributes = 0;
      std::vector<long>   numbers;      // the elements' numbers (from 1): places in the file, or a decomposition's global numbers
      std::vector<long>   ids;          // their global ids (the element map), Peridigm's point numbers
      std::vector<long>   connectivity; // node indices (from 0), nodes_per_element per element
      std::vector<double> attributes;   // n_attributes per element
    };
    /// In the file's order; within a block, the elements in the order of
    /// their global numbers.
    std::vector<Block> blocks;

    struct Set
    {
      long              id;
      std::string       name;  // "nodelist_<id>" / "surfacelist_<id>" if the file names none
      std::vector<long> items; // node indices (from 0), or elements' global numbers
      std::vector<int>  sides; // side sets: the side of each element (from 1, Exodus's numbering)
    };
    std::vector<Set> node_sets, side_sets;

    /// The pieces read: 1, or N for a decomposed file.
    unsigned int pieces = 1;
  };

  /// Reads @p file, or, if it does not exist, the pieces FILE.N.i of its
  /// decomposition. Refuses (AssertThrow, a message beginning with @p key and
  /// the file) what is not an Exodus II file (not netCDF, truncated, missing
  /// variables), a mesh that is not 3D, and names that repeat.
  ExodusMesh
  read_exodus_file(const std::string &file, const std::string &key);
} // namespace perideal
