# Is the mass of the green cube greater than half that of the purple cube?
# expected: yes

def execute_command(video):
    rope_scene = SoftScene(video, 'rope')
    green_cube = rope_scene.find("green cube")
    purple_cube = rope_scene.find("purple cube")

    # query_pair, not two query_single calls: it knows whether the two can be compared.
    green_cube_mass, purple_cube_mass = rope_scene.query_pair('mass', green_cube, purple_cube)

    if green_cube_mass is not None and purple_cube_mass is not None:
        return bool_to_yesno(green_cube_mass > 0.5 * purple_cube_mass)
    else:
        return "can not answer"
