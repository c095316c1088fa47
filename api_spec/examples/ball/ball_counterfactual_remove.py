# If we removed the white floating wall and other balls, which pit would the red ball drop into? | The right pit
# expected: yes

def execute_command(video):
    ball_scene = SoftScene(video, 'ball')
    red_ball = ball_scene.find("red ball")
    right_pit = ball_scene.find("right pit")

    # The wall and the other balls go together: the red ball falls alone.
    cf_init_event = ball_scene.register_event([], "remove", "white floating wall and other balls")
    ball_cf_scene = ball_scene.init_dyn_simulation(cf_init_event)

    flag = ball_cf_scene.happen(red_ball, "droping", right_pit)
    return bool_to_yesno(flag)
