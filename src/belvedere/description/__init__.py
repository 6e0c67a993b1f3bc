"""Robot descriptions: xacro, URDF models, checks and meshes."""
