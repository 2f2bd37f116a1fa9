"""What students get besides the notebooks: course meshes, procedural shapes, pictures, input checks.

``import starter`` stays light: pyvista and matplotlib are imported only when
a picture is drawn.
"""

from starter import plotting, shapes, validation
from starter.meshes import load_handles, load_mesh, mesh_names

__all__ = ["load_mesh", "load_handles", "mesh_names", "plotting", "shapes", "validation"]
