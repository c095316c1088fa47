# If we removed the black floating wall and other balls, which pit would the green ball drop into?
# expected: B
# A. Neither pit
# B. The left pit
# C. The right pit

def execute_command(video):
    ball_scene = SoftScene(video, 'ball')
    green_ball = ball_scene.find("green ball")

    cf_init_event = ball_scene.register_event([], "remove", "black floating wall and other balls")
    ball_cf_scene = ball_scene.init_dyn_simulation(cf_init_event)

    into_left = ball_cf_scene.happen(green_ball, "droping", ball_scene.find("left pit"))
    into_right = ball_cf_scene.happen(green_ball, "droping", ball_scene.find("right pit"))
    correct = []
    if not into_left and not into_right:
        correct.append("A")
    if into_left:
        correct.append("B")
    if into_right:
        correct.append("C")
    return " ".join(correct)
