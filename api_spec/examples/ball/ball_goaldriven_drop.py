# What can we do to make the red ball drop into the left pit? | Remove the black floating wall and other balls
# expected: yes

def execute_command(video):
    ball_scene = SoftScene(video, 'ball')
    red_ball = ball_scene.find("red ball")
    left_pit = ball_scene.find("left pit")

    # The option is an event: start the scene it describes and check the goal there.
    gd_init_event = ball_scene.register_event([], "remove", "black floating wall and other balls")
    ball_gd_scene = ball_scene.init_dyn_simulation(gd_init_event)

    flag = ball_gd_scene.happen(red_ball, "droping", left_pit)
    return bool_to_yesno(flag)
