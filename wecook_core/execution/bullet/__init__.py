"""The PyBullet adapter: the scene's bodies, the Panda arms, the planning scene and the world built over them."""
