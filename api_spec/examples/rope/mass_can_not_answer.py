# Is the mass of the green cube greater than that of the pink sphere?
# expected: can not answer

def execute_command(video):
    rope_scene = SoftScene(video, 'rope')
    green_cube = rope_scene.find("green cube")
    pink_sphere = rope_scene.find("pink sphere")

    # The two loads hang in different rope-pulley groups, so the video cannot compare them:
    # query_pair returns (None, None).
    green_cube_mass, pink_sphere_mass = rope_scene.query_pair('mass', green_cube, pink_sphere)

    if green_cube_mass is None or pink_sphere_mass is None:
        return "can not answer"
    return bool_to_yesno(green_cube_mass > pink_sphere_mass)
