"""What a study is made of, before anything is simulated: the robot, the terrains, the commanded motions, the
paper's published figures and its reference statistics.
"""
