# Will the blue ball finally drop into the right pit? | Yes
# expected: yes

def execute_command(video):
    ball_scene = SoftScene(video, 'ball')
    blue_ball = ball_scene.find("blue ball")
    right_pit = ball_scene.find("right pit")

    # The factual future of the video: what happens after its last frame.
    pred_init_event = ball_scene.register_event([], "simulate", "")
    ball_pred_scene = ball_scene.init_dyn_simulation(pred_init_event)

    flag = ball_pred_scene.happen(blue_ball, "droping", right_pit)
    return bool_to_yesno(flag)
